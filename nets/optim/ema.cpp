#include "nets/optim/ema.h"

#include "runtime/error.h"

namespace smokesvd::optim {

Ema::Ema(Context& context, NamedParameters parameters, double decay)
    : parameters_(std::move(parameters)), decay_(decay) {
  if (!(decay >= 0 && decay <= 1)) throw Error("EMA: decay must be in [0, 1], got " + std::to_string(decay));
  for (const auto& [name, parameter] : parameters_) values_.push_back(parameter->value);
  layout_ = flatLayout(values_);
  shadows_ = zeroState(context, layout_, values_);
  gathered_ = zeroFlat(context, layout_);
  optim::restoreState(values_, shadows_, layout_);
}

void Ema::update(Stream& stream) const {
  const Kernel& kernel = stream.kernel("nn/ema", {128, 1, 1});
  auto record = [&](const Tensor& shadow, const Tensor& value, int64_t n) {
    struct { uint32_t n; float decay; } push{static_cast<uint32_t>(n), static_cast<float>(decay_)};
    stream.dispatchFlat(kernel, {asVec4(shadow), asVec4(value), shadow}, push, (n + 3) / 4);
  };
  const FlatParts parts = flatParts(layout_, values_);
  stream.gather(parts.tensors, parts.offsets, gathered_);
  if (!parts.tensors.empty()) record(shadows_.flat, gathered_, layout_.total);
  for (std::size_t i = 0; i < values_.size(); ++i)
    if (!layout_.gathered(i)) record(shadows_.alone[i], values_[i], values_[i].numel());
}

void Ema::copyToParameters(Stream& stream) const { recordCopyOut(stream, shadows_, layout_, values_); }

std::vector<std::pair<std::string, Tensor>> Ema::namedShadows() const {
  std::vector<std::pair<std::string, Tensor>> like;
  for (const auto& [name, parameter] : parameters_) like.emplace_back(name, parameter->value);
  return copyState(shadows_, layout_, like);
}

void Ema::restoreShadows(const std::vector<std::pair<std::string, Tensor>>& shadows) {
  if (shadows.size() != parameters_.size())
    throw Error("EMA: restoring " + std::to_string(shadows.size()) + " shadows, expected " +
                std::to_string(parameters_.size()));
  std::vector<Tensor> from;
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    const auto& [name, shadow] = shadows[i];
    if (name != parameters_[i].first || shadow.shape() != values_[i].shape())
      throw Error("EMA: restoring shadow " + std::to_string(i) + " '" + name + "' " + toString(shadow.shape()) +
                  ", expected '" + parameters_[i].first + "' " + toString(values_[i].shape()));
    from.push_back(shadow);
  }
  optim::restoreState(from, shadows_, layout_);
}

}  // namespace smokesvd::optim

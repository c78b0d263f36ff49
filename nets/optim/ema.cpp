#include "nets/optim/ema.h"

#include "runtime/error.h"

namespace smokesvd::optim {

Ema::Ema(Context& context, NamedParameters parameters, double decay)
    : parameters_(std::move(parameters)), decay_(decay) {
  if (!(decay >= 0 && decay <= 1)) throw Error("EMA: decay must be in [0, 1], got " + std::to_string(decay));
  Stream copy(context);
  for (const auto& [name, parameter] : parameters_) {
    shadows_.emplace_back(context, parameter->value.shape());
    copy.copy(parameter->value, shadows_.back());
  }
  copy.submit();
}

void Ema::update(Stream& stream) const {
  const Kernel& kernel = stream.kernel("nn/ema", {128, 1, 1});
  for (std::size_t i = 0; i < shadows_.size(); ++i) {
    const Tensor& shadow = shadows_[i];
    struct { uint32_t n; float decay; } push{static_cast<uint32_t>(shadow.numel()), static_cast<float>(decay_)};
    stream.dispatchFlat(kernel, {asVec4(shadow), asVec4(parameters_[i].second->value), shadow}, push,
                        (shadow.numel() + 3) / 4);
  }
}

void Ema::copyToParameters(Stream& stream) const {
  for (std::size_t i = 0; i < shadows_.size(); ++i) stream.copy(shadows_[i], parameters_[i].second->value);
}

std::vector<std::pair<std::string, Tensor>> Ema::namedShadows() const {
  std::vector<std::pair<std::string, Tensor>> named;
  for (std::size_t i = 0; i < shadows_.size(); ++i) named.emplace_back(parameters_[i].first, shadows_[i]);
  return named;
}

}  // namespace smokesvd::optim

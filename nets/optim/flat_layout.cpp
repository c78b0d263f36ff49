#include "nets/optim/flat_layout.h"

namespace smokesvd::optim {

FlatLayout flatLayout(std::span<const Tensor> tensors) {
  FlatLayout layout;
  int64_t next = 0;
  for (const Tensor& tensor : tensors) {
    if (tensor.numel() > FlatLayout::kMaxGatheredElements) {
      layout.offsets.push_back(-1);
      continue;
    }
    layout.offsets.push_back(next);
    next += (tensor.numel() + 3) / 4 * 4;
  }
  layout.total = std::max<int64_t>(next, 4);
  return layout;
}

Tensor zeroFlat(Context& context, const FlatLayout& layout) {
  Tensor flat(context, {layout.total});
  Stream zero(context);
  zero.fillZero(flat);
  zero.submit();
  return flat;
}

FlatState zeroState(Context& context, const FlatLayout& layout, std::span<const Tensor> tensors) {
  FlatState state{zeroFlat(context, layout), {}};
  Stream zero(context);
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    state.alone.emplace_back();
    if (layout.gathered(i)) continue;
    state.alone.back() = Tensor(context, tensors[i].shape());
    zero.fillZero(state.alone.back());
  }
  zero.submit();
  return state;
}

void recordCopyOut(Stream& stream, const FlatState& state, const FlatLayout& layout, std::span<const Tensor> to) {
  const FlatParts parts = flatParts(layout, to);
  stream.scatter(state.flat, parts.offsets, parts.tensors);
  for (std::size_t i = 0; i < to.size(); ++i)
    if (!layout.gathered(i)) stream.copy(state.alone[i], to[i]);
}

void recordCopyIn(Stream& stream, std::span<const Tensor> from, const FlatState& state, const FlatLayout& layout) {
  const FlatParts parts = flatParts(layout, from);
  stream.gather(parts.tensors, parts.offsets, state.flat);
  for (std::size_t i = 0; i < from.size(); ++i)
    if (!layout.gathered(i)) stream.copy(from[i], state.alone[i]);
}

std::vector<std::pair<std::string, Tensor>> copyState(const FlatState& state, const FlatLayout& layout,
                                                      const std::vector<std::pair<std::string, Tensor>>& like) {
  std::vector<std::pair<std::string, Tensor>> named;
  std::vector<Tensor> copies;
  for (const auto& [name, tensor] : like) {
    copies.emplace_back(state.flat.context(), tensor.shape());
    named.emplace_back(name, copies.back());
  }
  Stream copy(state.flat.context());
  recordCopyOut(copy, state, layout, copies);
  copy.submit();
  return named;
}

void restoreState(std::span<const Tensor> from, const FlatState& state, const FlatLayout& layout) {
  Stream restore(state.flat.context());
  recordCopyIn(restore, from, state, layout);
  restore.submit();
}

}  // namespace smokesvd::optim

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

std::vector<std::pair<std::string, Tensor>> copyState(const FlatState& state, const FlatLayout& layout,
                                                      const std::vector<std::pair<std::string, Tensor>>& like) {
  const Tensor& flat = state.flat;
  std::vector<std::pair<std::string, Tensor>> named;
  std::vector<Tensor> copies;
  for (const auto& [name, tensor] : like) {
    copies.emplace_back(flat.context(), tensor.shape());
    named.emplace_back(name, copies.back());
  }
  Stream copy(flat.context());
  const FlatParts parts = flatParts(layout, copies);
  copy.scatter(flat, parts.offsets, parts.tensors);
  for (std::size_t i = 0; i < copies.size(); ++i)
    if (!layout.gathered(i)) copy.copy(state.alone[i], copies[i]);
  copy.submit();
  return named;
}

void restoreState(std::span<const Tensor> from, const FlatState& state, const FlatLayout& layout) {
  Stream restore(state.flat.context());
  const FlatParts parts = flatParts(layout, from);
  restore.gather(parts.tensors, parts.offsets, state.flat);
  for (std::size_t i = 0; i < from.size(); ++i)
    if (!layout.gathered(i)) restore.copy(from[i], state.alone[i]);
  restore.submit();
}

}  // namespace smokesvd::optim

// Small tensors laid end to end in one flat tensor, each from a multiple of four elements (one vec4 texel)
// on, the elements between them zero. The optimiser's kernels (Adam, the EMA, the gradient norm) run once
// over such a tensor instead of once per small parameter tensor: a UNet's 150 parameter tensors, most of
// them biases and small weights, would otherwise cost 150 dispatches each, and lavapipe pays 15 to 100
// microseconds per dispatch where a transfer command costs about one (docs/nn-training.md, "One dispatch
// for the small parameters"). Tensors of more than kMaxGatheredElements elements stay where they are and
// get a dispatch of their own.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::optim {

struct FlatLayout {
  // 131072 elements: on lavapipe a tensor's own three dispatches (norm, AdamW, EMA) cost more than copying it in
  // and out, up to about this size; past it the update gains nothing (docs/nn-training.md, measured).
  static constexpr int64_t kMaxGatheredElements = 131072;

  std::vector<int64_t> offsets;  // per tensor: the element it starts at in the flat tensor, or -1
  int64_t total = 4;             // the flat tensor's elements: a multiple of 4, at least 4

  bool gathered(std::size_t i) const { return offsets[i] >= 0; }
};

FlatLayout flatLayout(std::span<const Tensor> tensors);

// A flat tensor of the layout, all zero (recorded and run on a stream of its own).
Tensor zeroFlat(Context& context, const FlatLayout& layout);

// The gathered tensors of `tensors` (laid out by `layout`) for which keep(i) holds, with their offsets:
// the arguments of Stream::gather and Stream::scatter.
struct FlatParts {
  std::vector<Tensor> tensors;
  std::vector<int64_t> offsets;
};
template <typename Keep>
FlatParts flatParts(const FlatLayout& layout, std::span<const Tensor> tensors, Keep keep) {
  FlatParts parts;
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    if (!layout.gathered(i) || !keep(i)) continue;
    parts.tensors.push_back(tensors[i]);
    parts.offsets.push_back(layout.offsets[i]);
  }
  return parts;
}
inline FlatParts flatParts(const FlatLayout& layout, std::span<const Tensor> tensors) {
  return flatParts(layout, tensors, [](std::size_t) { return true; });
}

// State kept per tensor (Adam's moments, the EMA's shadows): the gathered tensors' in one flat tensor of the
// layout, each other tensor's in a tensor of its own.
struct FlatState {
  Tensor flat;
  std::vector<Tensor> alone;  // per tensor of the layout; undefined for the gathered ones
};

// All zero, shaped like `tensors` (laid out by `layout`).
FlatState zeroState(Context& context, const FlatLayout& layout, std::span<const Tensor> tensors);
// Records copying the state out into `to` (one tensor per tensor of the layout, in order), or in from `from`.
void recordCopyOut(Stream& stream, const FlatState& state, const FlatLayout& layout, std::span<const Tensor> to);
void recordCopyIn(Stream& stream, std::span<const Tensor> from, const FlatState& state, const FlatLayout& layout);
// Named copies of the state per tensor; names and shapes from `like` (in the layout's order).
std::vector<std::pair<std::string, Tensor>> copyState(const FlatState& state, const FlatLayout& layout,
                                                      const std::vector<std::pair<std::string, Tensor>>& like);
// The reverse: sets `state` from tensors such as copyState gives (in the layout's order).
void restoreState(std::span<const Tensor> from, const FlatState& state, const FlatLayout& layout);

}  // namespace smokesvd::optim

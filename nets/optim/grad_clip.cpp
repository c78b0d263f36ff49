#include "nets/optim/grad_clip.h"

#include <algorithm>
#include <unordered_set>

#include "nets/optim/flat_layout.h"
#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd::optim {
namespace {

constexpr uint64_t kMaxInvocationsPerTensor = 16384;
constexpr uint64_t kTexelsPerInvocation = 16;

// The reducing kernels' workgroup: one subgroup (a power of two: the shared-memory tree halves it).
uint32_t reduceWorkgroup(const Context& context) { return context.info().reductionWorkgroup(); }

uint64_t partialsFor(int64_t elements, uint32_t workgroup) {
  const uint64_t texels = (static_cast<uint64_t>(elements) + 3) / 4;
  return std::clamp<uint64_t>(texels / (workgroup * kTexelsPerInvocation), 1, kMaxInvocationsPerTensor / workgroup);
}

}  // namespace

GradClip::GradClip(Context& context, double maxNorm) : maxNorm_(maxNorm), result_(context, {2}) {
  if (!(maxNorm > 0)) throw Error("gradient clipping: maxNorm must be > 0, got " + std::to_string(maxNorm));
  result_.upload(std::vector<float>{0.0f, 1.0f});
}

void GradClip::record(Stream& stream, const NamedParameters& parameters) const {
  std::vector<Tensor> gradients;
  for (const auto& [name, parameter] : parameters)
    if (parameter->grad.defined() && parameter->grad.numel() > 0) gradients.push_back(parameter->grad);
  // The small gradients end to end in one flat tensor (flat_layout.h), zero between them, summed in one
  // pass; each large one in a pass of its own. Every pass writes its own range of partial sums.
  const FlatLayout layout = flatLayout(gradients);
  const FlatParts small = flatParts(layout, gradients);
  const uint32_t workgroup = reduceWorkgroup(stream.context());
  std::vector<std::pair<Tensor, int64_t>> passes;  // tensor, elements
  if (!small.tensors.empty()) {
    const Tensor flat(stream.context(), {layout.total});
    stream.fillZero(flat);
    stream.gather(small.tensors, small.offsets, flat);
    passes.emplace_back(flat, layout.total);
  }
  for (std::size_t i = 0; i < gradients.size(); ++i)
    if (!layout.gathered(i)) passes.emplace_back(gradients[i], gradients[i].numel());
  uint64_t count = 0;
  for (const auto& [tensor, elements] : passes) count += partialsFor(elements, workgroup);
  const Tensor partials(stream.context(), {static_cast<int64_t>(std::max<uint64_t>(count, 1))});
  if (count == 0) stream.fillZero(partials);

  const Kernel& norm = stream.kernel("nn/grad_norm", {workgroup, 1, 1});
  uint64_t offset = 0;
  for (const auto& [tensor, elements] : passes) {
    const uint64_t groups = partialsFor(elements, workgroup);
    struct { uint32_t n, offset; } push{static_cast<uint32_t>(elements), static_cast<uint32_t>(offset)};
    stream.dispatch(norm, {asVec4(tensor), partials}, push, {static_cast<uint32_t>(groups), 1, 1});
    offset += groups;
  }
  struct { uint32_t count; float maxNorm; } push{static_cast<uint32_t>(std::max<uint64_t>(count, 1)),
                                                 static_cast<float>(maxNorm_)};
  stream.dispatch(stream.kernel("nn/clip_factor", {workgroup, 1, 1}), {partials, result_}, push, {1, 1, 1});
}

void GradClip::scaleGradients(Stream& stream, const NamedParameters& parameters) const {
  const Kernel& scale = stream.kernel("nn/clip_grad", {128, 1, 1});
  std::unordered_set<const Buffer*> scaled;  // autograd may give two parameters the same gradient tensor
  for (const auto& [name, parameter] : parameters) {
    const Tensor& gradient = parameter->grad;
    if (!gradient.defined() || gradient.numel() == 0 || !scaled.insert(&gradient.buffer()).second) continue;
    struct { uint32_t n; } push{static_cast<uint32_t>(gradient.numel())};
    stream.dispatchFlat(scale, {result_, asVec4(gradient), gradient}, push, (gradient.numel() + 3) / 4);
  }
}

float GradClip::norm() const { return result_.download()[0]; }
float GradClip::factor() const { return result_.download()[1]; }

}  // namespace smokesvd::optim

#include "nets/optim/grad_clip.h"

#include <algorithm>
#include <unordered_set>

#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd::optim {
namespace {

constexpr uint64_t kMaxInvocationsPerGradient = 16384;
constexpr uint64_t kTexelsPerInvocation = 16;

// The reducing kernels' workgroup: one subgroup (a power of two: the shared-memory tree halves it).
uint32_t reduceWorkgroup(const Context& context) { return context.info().reductionWorkgroup(); }

uint64_t partialsFor(const Tensor& gradient, uint32_t workgroup) {
  const uint64_t texels = (static_cast<uint64_t>(gradient.numel()) + 3) / 4;
  return std::clamp<uint64_t>(texels / (workgroup * kTexelsPerInvocation), 1, kMaxInvocationsPerGradient / workgroup);
}

}  // namespace

GradClip::GradClip(Context& context, double maxNorm) : maxNorm_(maxNorm), result_(context, {2}) {
  if (!(maxNorm > 0)) throw Error("gradient clipping: maxNorm must be > 0, got " + std::to_string(maxNorm));
  result_.upload(std::vector<float>{0.0f, 1.0f});
}

void GradClip::record(Stream& stream, const NamedParameters& parameters) const {
  const uint32_t workgroup = reduceWorkgroup(stream.context());
  uint64_t count = 0;
  for (const auto& [name, parameter] : parameters)
    if (parameter->grad.defined() && parameter->grad.numel() > 0) count += partialsFor(parameter->grad, workgroup);
  Tensor partials(stream.context(), {static_cast<int64_t>(std::max<uint64_t>(count, 1))});
  if (count == 0) stream.fillZero(partials);

  const Kernel& norm = stream.kernel("nn/grad_norm", {workgroup, 1, 1});
  uint64_t offset = 0;
  for (const auto& [name, parameter] : parameters) {
    const Tensor& gradient = parameter->grad;
    if (!gradient.defined() || gradient.numel() == 0) continue;
    const uint64_t groups = partialsFor(gradient, workgroup);
    struct { uint32_t n, offset; } push{static_cast<uint32_t>(gradient.numel()), static_cast<uint32_t>(offset)};
    stream.dispatch(norm, {asVec4(gradient), partials}, push, {static_cast<uint32_t>(groups), 1, 1});
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

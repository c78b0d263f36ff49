#include "nets/ops/reduce.h"

#include <algorithm>

#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr uint64_t kMaxInvocations = 65536;  // of pass 1; pass 2 runs one workgroup over its partials
constexpr uint64_t kTexelsPerInvocation = 16;

}  // namespace

void reduceAll(Stream& stream, Reduction reduction, const Tensor& x, const Tensor& out) {
  if (x.numel() == 0) throw Error("reduce: the input tensor " + toString(x.shape()) + " is empty");
  if (out.numel() != 1) throw Error("reduce: the output must hold one element, got " + toString(out.shape()));
  const int32_t isMax = reduction == Reduction::Max ? 1 : 0;
  // One subgroup per workgroup (a power of two: the shared-memory tree halves it).
  const uint32_t workgroup = stream.context().info().reductionWorkgroup();
  const Kernel& kernel = stream.kernel("tensor/reduce", {workgroup, 1, 1}, {isMax});
  const uint64_t texels = (static_cast<uint64_t>(x.numel()) + 3) / 4;
  const uint64_t groups = std::clamp<uint64_t>(texels / (workgroup * kTexelsPerInvocation), 1, kMaxInvocations / workgroup);
  const float meanScale = reduction == Reduction::Mean ? 1.0f / static_cast<float>(x.numel()) : 1.0f;
  struct Push { uint32_t n; float scale; };

  if (groups == 1) {
    stream.dispatch(kernel, {asVec4(x), out}, Push{static_cast<uint32_t>(x.numel()), meanScale}, {1, 1, 1});
    return;
  }
  Tensor partials(stream.context(), {static_cast<int64_t>(groups)});
  stream.dispatch(kernel, {asVec4(x), partials}, Push{static_cast<uint32_t>(x.numel()), 1.0f},
                  {static_cast<uint32_t>(groups), 1, 1});
  stream.dispatch(kernel, {asVec4(partials), out}, Push{static_cast<uint32_t>(groups), meanScale}, {1, 1, 1});
}

}  // namespace smokesvd::ops

#include "nets/ops/group_norm.h"

#include <algorithm>

#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr int32_t kChunk = 4096;           // elements one reducing workgroup covers
constexpr int64_t kMaxGroups = 65535;

// The reducing kernels' workgroup (a power of two: the shared-memory tree halves it); the per-plane
// kernels use the same size.
uint32_t reduceWorkgroup(const Stream& stream) { return stream.context().info().reductionWorkgroup(); }

int32_t chunksOf(int64_t elements) { return static_cast<int32_t>((elements + kChunk - 1) / kChunk); }
int32_t vec4When(int64_t elements) { return elements % 4 == 0 ? 1 : 0; }
int32_t siluFlag(NormActivation activation) { return activation == NormActivation::Silu ? 1 : 0; }

void requireShape(const char* name, const Tensor& tensor, const Shape& expected) {
  if (tensor.shape() != expected)
    throw Error(std::string("group norm: ") + name + " has shape " + toString(tensor.shape()) + ", expected " +
                toString(expected));
}

// Grid of the per-plane kernels: chunks of a plane along x, planes along y.
std::array<uint32_t, 3> planeGrid(const GroupNormShape& s) {
  return {static_cast<uint32_t>(chunksOf(s.planeSize)), static_cast<uint32_t>(s.batch * s.channels), 1};
}

struct PlanePush {
  int32_t planeSize, channels, channelsPerGroup;
};

PlanePush planePush(const GroupNormShape& s) {
  return {static_cast<int32_t>(s.planeSize), static_cast<int32_t>(s.channels),
          static_cast<int32_t>(s.channels / s.groups)};
}

}  // namespace

GroupNormShape groupNormShape(const Shape& shape, int64_t groups) {
  if (shape.size() < 3 || numElements(shape) == 0)
    throw Error("group norm: expected a non-empty N,C,spatial... tensor, got " + toString(shape));
  if (groups < 1 || shape[1] % groups != 0)
    throw Error("group norm: " + std::to_string(groups) + " groups do not divide " + std::to_string(shape[1]) +
                " channels");
  if (shape[0] * shape[1] > kMaxGroups)
    throw Error("group norm: batch x channels of " + toString(shape) + " exceeds " + std::to_string(kMaxGroups));
  return {shape[0], shape[1], groups, numElements(shape) / (shape[0] * shape[1])};
}

void groupNormStats(Stream& stream, const Tensor& x, int64_t groups, float eps, const Tensor& stats) {
  const GroupNormShape s = groupNormShape(x.shape(), groups);
  requireShape("stats", stats, {s.batch * groups, 2});
  const int64_t groupSize = s.channels / groups * s.planeSize;
  const int32_t chunks = chunksOf(groupSize);
  const int32_t blocks = static_cast<int32_t>(s.batch * groups);
  // A group of one chunk: the first pass writes the statistics itself.
  const bool oneChunk = chunks == 1;
  const Tensor partial = oneChunk ? stats : Tensor(stream.context(), {blocks, chunks, 2});

  struct { int32_t groupSize, chunks; float eps; } statsPush{static_cast<int32_t>(groupSize), chunks, eps};
  const int32_t vec4 = vec4When(groupSize);
  stream.dispatch(stream.kernel("nn/group_norm_stats", {reduceWorkgroup(stream), 1, 1}, {vec4, kChunk, oneChunk ? 1 : 0}),
                  {vec4 ? asVec4(x) : Arg(x), partial}, statsPush,
                  {static_cast<uint32_t>(chunks), static_cast<uint32_t>(blocks), 1});
  if (oneChunk) return;

  struct { int32_t groupSize, chunks, blocks; float eps; } finalizePush{static_cast<int32_t>(groupSize), chunks,
                                                                        blocks, eps};
  stream.dispatchFlat(stream.kernel("nn/group_norm_finalize", {64, 1, 1}, {kChunk}), {partial, stats}, finalizePush,
                      static_cast<uint64_t>(blocks));
}

void groupNormForward(Stream& stream, const Tensor& x, const Tensor& gamma, const Tensor& beta, int64_t groups,
                      float eps, const Tensor& y, const Tensor& stats, NormActivation activation) {
  const GroupNormShape s = groupNormShape(x.shape(), groups);
  requireShape("gamma", gamma, {s.channels});
  requireShape("beta", beta, {s.channels});
  requireShape("y", y, x.shape());
  groupNormStats(stream, x, groups, eps, stats);
  const int32_t planeVec4 = vec4When(s.planeSize);
  stream.dispatch(stream.kernel("nn/group_norm_apply", {reduceWorkgroup(stream), 1, 1},
                                {planeVec4, kChunk, siluFlag(activation)}),
                  {planeVec4 ? asVec4(x) : Arg(x), gamma, beta, stats, y}, planePush(s), planeGrid(s));
}

void groupNormBackward(Stream& stream, const Tensor& x, const Tensor& gamma, const Tensor& beta, const Tensor& stats,
                       int64_t groups, const Tensor& gy, const Tensor& gx, const Tensor& ggamma, const Tensor& gbeta,
                       NormActivation activation) {
  const GroupNormShape s = groupNormShape(x.shape(), groups);
  requireShape("gamma", gamma, {s.channels});
  requireShape("beta", beta, {s.channels});
  requireShape("stats", stats, {s.batch * groups, 2});
  requireShape("gy", gy, x.shape());
  requireShape("gx", gx, x.shape());
  requireShape("ggamma", ggamma, gamma.shape());
  requireShape("gbeta", gbeta, gamma.shape());
  const int32_t chunks = chunksOf(s.planeSize);
  const int64_t planes = s.batch * s.channels;
  Tensor partial(stream.context(), {planes, chunks, 2});
  Tensor coef(stream.context(), {s.batch * groups, 2});

  const int32_t vec4 = vec4When(s.planeSize);
  const Arg xArg = vec4 ? asVec4(x) : Arg(x);
  const Arg gyArg = vec4 ? asVec4(gy) : Arg(gy);
  const int32_t silu = siluFlag(activation);
  struct { int32_t planeSize, chunks, channelsPerGroup, channels; } reducePush{
      static_cast<int32_t>(s.planeSize), chunks, static_cast<int32_t>(s.channels / groups),
      static_cast<int32_t>(s.channels)};
  stream.dispatch(stream.kernel("nn/group_norm_backward_reduce", {reduceWorkgroup(stream), 1, 1}, {vec4, kChunk, silu}),
                  {xArg, gyArg, stats, gamma, beta, partial}, reducePush,
                  {static_cast<uint32_t>(chunks), static_cast<uint32_t>(planes), 1});

  struct { int32_t batch, channels, groups, chunks; float invGroupSize; } finalizePush{
      static_cast<int32_t>(s.batch), static_cast<int32_t>(s.channels), static_cast<int32_t>(groups), chunks,
      1.0f / static_cast<float>(s.channels / groups * s.planeSize)};
  stream.dispatchFlat(stream.kernel("nn/group_norm_backward_finalize", {64, 1, 1}),
                      {partial, gamma, ggamma, gbeta, coef}, finalizePush,
                      static_cast<uint64_t>(std::max(s.channels, s.batch * groups)));

  stream.dispatch(stream.kernel("nn/group_norm_backward_apply", {reduceWorkgroup(stream), 1, 1}, {vec4, kChunk, silu}),
                  {xArg, gyArg, gamma, beta, stats, coef, gx}, planePush(s), planeGrid(s));
}

}  // namespace smokesvd::ops

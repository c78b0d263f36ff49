#include "pipeline/render/atomics.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>

#include "nets/ops/reduce_axes.h"

namespace smokesvd::render {

std::string scatterKernel(const Context& context, const std::string& shader) {
  return context.info().float32AtomicAdd ? shader : shader + "_cas";
}

bool deterministicScatter(const Context& context) {
  const char* fast = std::getenv("SMOKESVD_FAST_SCATTER");
  if (fast != nullptr && std::strcmp(fast, "1") == 0) return false;
  return context.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU;
}

int scatterShards(const Context& context, uint64_t items, uint64_t iterationsPerItem, uint32_t workgroup) {
  if (!deterministicScatter(context)) return 1;
  // Each invocation visits ceil(items / (shards * workgroup)) items and one loop iteration more per item.
  const uint64_t perShard = kLoopIterationBudget / (iterationsPerItem + 1) * workgroup;
  const uint64_t shards = (items + perShard - 1) / std::max<uint64_t>(perShard, 1);
  return static_cast<int>(std::max<uint64_t>(shards, kMinScatterShards));
}

Tensor scatterTarget(Stream& stream, const Tensor& output, int shards) {
  Tensor target = shards == 1 ? output : Tensor(stream.context(), {shards, output.numel()});
  stream.fillZero(target);
  return target;
}

void sumShards(Stream& stream, const Tensor& target, int shards, const Tensor& output) {
  if (shards == 1) return;
  const std::array<int, 1> axes{0};
  ops::reduceAxes(stream, ops::ReduceMap::Identity, target, nullptr, axes, 1.0f, output);
}

bool adjointsByPlanes(const Context& context, const ViewSet& views) {
  return deterministicScatter(context) && views.raysInVoxelRows;
}

}  // namespace smokesvd::render

// Kernels that scatter gradients add floats atomically: with float32 atomic add
// (VK_EXT_shader_atomic_float) where the device has it, otherwise with compare-and-swap loops that every
// Vulkan device runs (shaders/common/float_atomic_add.glsl). Each such kernel is built both ways.
//
// On CPU devices (lavapipe) the sums are made deterministic: the kernel runs as a few workgroups (shards)
// whose invocations stride over the items, workgroup s visits its share in a fixed order and adds into
// a zeroed copy of each output of its own (elements s*n .. s*n+n-1 of the target, n the output's size:
// the kernels read n as shard_size, 0 when there is one shard), and sumShards adds the copies in shard
// order. Training and gradients are then reproducible bit for bit while every core works. GPUs run the
// kernel wide into the output itself and add in whatever order the atomics land.
// SMOKESVD_FAST_SCATTER=1 runs it wide everywhere. (On CPU devices, views whose rays all run in voxel rows
// skip the scatter: their adjoints run by voxel planes, without atomics; ViewSet::raysInVoxelRows.)
//
// The number of shards also keeps every invocation under llvmpipe's loop limit (kLoopIterationBudget,
// runtime/device_info.h): a single striding workgroup passed it on the paper's volumes, and the render
// adjoint of 16 views at 112x64 silently lost a third of its gradient.
#pragma once

#include <algorithm>
#include <array>
#include <string>

#include "pipeline/render/view_set.h"
#include "runtime/context.h"
#include "runtime/stream.h"

namespace smokesvd::render {

// The fewest shards of a deterministic scatter (one per core of the project's 2-core machine).
constexpr int kMinScatterShards = 2;

// The name of the variant of scattering kernel `shader` (e.g. "render/lift_adjoint") for this device:
// the shader itself, or its "_cas" variant without float atomics.
std::string scatterKernel(const Context& context, const std::string& shader);

// Whether scattered sums come out the same on every run.
bool deterministicScatter(const Context& context);
// The shards of a scatter over `items` items, each running at most `iterationsPerItem` loop iterations,
// with `workgroup` invocations per workgroup: 1 where the scatter is not deterministic, else at least
// kMinScatterShards and enough that no invocation runs more than kLoopIterationBudget iterations.
int scatterShards(const Context& context, uint64_t items, uint64_t iterationsPerItem, uint32_t workgroup);

// The zeroed buffer a scattering kernel adds into for `output`: the output itself with one shard, else
// `shards` copies of its size.
Tensor scatterTarget(Stream& stream, const Tensor& output, int shards);
// output = the sum of the shards' copies in shard order (nothing to do with one shard).
void sumShards(Stream& stream, const Tensor& target, int shards, const Tensor& output);

// Records a scattering kernel over `items` items (the kernel strides by flat_invocations()): one
// workgroup per shard, or one invocation per item with one shard. `push` ends with the shard size.
template <typename Push>
void dispatchScatter(Stream& stream, const Kernel& kernel, std::initializer_list<Arg> args, const Push& push,
                     uint64_t items, int shards) {
  if (shards > 1)
    stream.dispatch(kernel, args, push, {static_cast<uint32_t>(shards), 1, 1});
  else
    stream.dispatchFlat(kernel, args, push, items);
}

// Whether the adjoints of `views` run by voxel planes instead of scattering: on CPU devices
// (deterministicScatter) where every ray runs in a voxel row (ViewSet::raysInVoxelRows), each voxel plane goes
// to one invocation that adds without atomics (shaders/render/*_rows.comp).
bool adjointsByPlanes(const Context& context, const ViewSet& views);

// The workgroup of a kernel by voxel planes: one invocation per plane, the width of llvmpipe's vectors.
constexpr std::array<uint32_t, 3> kPlaneWorkgroup{8, 1, 1};

// Records a kernel by voxel planes (built with kPlaneWorkgroup) over `planes` planes and views
// [0, views): as many views a dispatch as keep an invocation under kLoopIterationBudget at
// `iterationsPerView` loop iterations a view; push(first, count) gives a dispatch's push constants.
template <typename MakePush>
void dispatchByPlanes(Stream& stream, const Kernel& kernel, std::initializer_list<Arg> args, int64_t planes,
                      int views, uint64_t iterationsPerView, MakePush push) {
  const int perDispatch = static_cast<int>(std::max<uint64_t>(1, kLoopIterationBudget / iterationsPerView));
  const auto groups = static_cast<uint32_t>((planes + kPlaneWorkgroup[0] - 1) / kPlaneWorkgroup[0]);
  for (int first = 0; first < views; first += perDispatch)
    stream.dispatch(kernel, args, push(first, std::min(perDispatch, views - first)), {groups, 1, 1});
}

}  // namespace smokesvd::render

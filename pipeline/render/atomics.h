// Kernels that scatter gradients add floats atomically: with float32 atomic add
// (VK_EXT_shader_atomic_float) where the device has it, otherwise with compare-and-swap loops that every
// Vulkan device runs (shaders/common/float_atomic_add.glsl). Each such kernel is built both ways.
#pragma once

#include <string>

#include "runtime/context.h"
#include "runtime/stream.h"

namespace smokesvd::render {

// The name of the variant of scattering kernel `shader` (e.g. "render/lift_adjoint") for this device:
// the shader itself, or its "_cas" variant without float atomics.
std::string scatterKernel(const Context& context, const std::string& shader);

// Whether scattered sums come out the same on every run. On CPU devices (lavapipe) a scattering kernel
// runs as one workgroup whose invocations stride over the items in a fixed order, so training and
// gradients are reproducible bit for bit (at the price of one core for that kernel); GPUs run it wide
// and add in whatever order the atomics land. SMOKESVD_FAST_SCATTER=1 runs it wide everywhere.
bool deterministicScatter(const Context& context);

// Records a scattering kernel over `items` items (the kernel strides by flat_invocations()): one
// workgroup where the scatter is deterministic, else one invocation per item.
template <typename Push>
void dispatchScatter(Stream& stream, const Kernel& kernel, std::initializer_list<Arg> args, const Push& push,
                     uint64_t items) {
  if (deterministicScatter(stream.context()))
    stream.dispatch(kernel, args, push, {1, 1, 1});
  else
    stream.dispatchFlat(kernel, args, push, items);
}

}  // namespace smokesvd::render

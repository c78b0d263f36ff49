// Kernels that scatter gradients add floats atomically: with float32 atomic add
// (VK_EXT_shader_atomic_float) where the device has it, otherwise with compare-and-swap loops that every
// Vulkan device runs (shaders/common/float_atomic_add.glsl). Each such kernel is built both ways.
#pragma once

#include <string>

#include "runtime/context.h"

namespace smokesvd::render {

// The name of the variant of scattering kernel `shader` (e.g. "render/lift_adjoint") for this device:
// the shader itself, or its "_cas" variant without float atomics.
std::string scatterKernel(const Context& context, const std::string& shader);

}  // namespace smokesvd::render

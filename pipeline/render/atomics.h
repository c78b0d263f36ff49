// Kernels that scatter gradients use float32 atomic adds on storage buffers (VK_EXT_shader_atomic_float).
#pragma once

#include "runtime/context.h"

namespace smokesvd::render {

// Throws Error naming `operation` and the device if the device lacks float32 atomic adds.
void requireFloatAtomics(const Context& context, const char* operation);

}  // namespace smokesvd::render

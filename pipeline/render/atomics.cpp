#include "pipeline/render/atomics.h"

#include "runtime/error.h"

namespace smokesvd::render {

void requireFloatAtomics(const Context& context, const char* operation) {
  if (!context.info().float32AtomicAdd)
    throw Error(std::string(operation) + ": device '" + context.info().name +
                "' lacks float32 atomic add on storage buffers (VK_EXT_shader_atomic_float), which this "
                "adjoint needs");
}

}  // namespace smokesvd::render

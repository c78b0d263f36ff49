#include "pipeline/render/atomics.h"

namespace smokesvd::render {

std::string scatterKernel(const Context& context, const std::string& shader) {
  return context.info().float32AtomicAdd ? shader : shader + "_cas";
}

}  // namespace smokesvd::render

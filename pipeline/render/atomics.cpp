#include "pipeline/render/atomics.h"

#include <cstdlib>
#include <cstring>

namespace smokesvd::render {

std::string scatterKernel(const Context& context, const std::string& shader) {
  return context.info().float32AtomicAdd ? shader : shader + "_cas";
}

bool deterministicScatter(const Context& context) {
  const char* fast = std::getenv("SMOKESVD_FAST_SCATTER");
  if (fast != nullptr && std::strcmp(fast, "1") == 0) return false;
  return context.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU;
}

}  // namespace smokesvd::render

#include "runtime/error.h"

namespace smokesvd {
namespace {

std::string describe(VkResult result, std::string_view doing) {
  std::string message(doing);
  message += ": ";
  message += vkResultName(result);
  switch (result) {
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: message += " (the GPU is out of memory; try a smaller preset)"; break;
    case VK_ERROR_OUT_OF_HOST_MEMORY: message += " (the host is out of memory)"; break;
    case VK_ERROR_DEVICE_LOST: message += " (the device was lost: driver crash, reset or a kernel ran too long)"; break;
    case VK_ERROR_INCOMPATIBLE_DRIVER: message += " (no compatible Vulkan driver is installed)"; break;
    default: break;
  }
  return message;
}

}  // namespace

VulkanError::VulkanError(VkResult result, std::string_view doing)
    : Error(describe(result, doing)), result_(result) {}

std::string_view vkResultName(VkResult result) {
  switch (result) {
#define SMOKESVD_RESULT(name) \
  case name: return #name;
    SMOKESVD_RESULT(VK_SUCCESS)
    SMOKESVD_RESULT(VK_NOT_READY)
    SMOKESVD_RESULT(VK_TIMEOUT)
    SMOKESVD_RESULT(VK_INCOMPLETE)
    SMOKESVD_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
    SMOKESVD_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    SMOKESVD_RESULT(VK_ERROR_INITIALIZATION_FAILED)
    SMOKESVD_RESULT(VK_ERROR_DEVICE_LOST)
    SMOKESVD_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
    SMOKESVD_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
    SMOKESVD_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
    SMOKESVD_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
    SMOKESVD_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
    SMOKESVD_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
    SMOKESVD_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
    SMOKESVD_RESULT(VK_ERROR_FRAGMENTED_POOL)
    SMOKESVD_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
    SMOKESVD_RESULT(VK_ERROR_INVALID_SHADER_NV)
    SMOKESVD_RESULT(VK_ERROR_UNKNOWN)
#undef SMOKESVD_RESULT
    default: return "VkResult(unknown)";
  }
}

}  // namespace smokesvd

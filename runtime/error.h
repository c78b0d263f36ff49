// Errors carry context: what was being done, on which object, and the Vulkan result when there is one.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include <vulkan/vulkan.h>

namespace smokesvd {

// Any failure the user can act on (bad input, no device, out of memory, ...). what() is one line.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A Vulkan call failed; result() tells which way.
class VulkanError : public Error {
 public:
  VulkanError(VkResult result, std::string_view doing);
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

std::string_view vkResultName(VkResult result);

// Throws VulkanError("<doing>: VK_ERROR_...") unless result is VK_SUCCESS.
inline void vkCheck(VkResult result, std::string_view doing) {
  if (result != VK_SUCCESS) throw VulkanError(result, doing);
}

}  // namespace smokesvd

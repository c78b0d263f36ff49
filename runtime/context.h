// The Vulkan context: instance, the chosen device, its compute queue, the buffer pool and the kernel cache.
// Create one per process; every Tensor, Kernel and Stream refers to it and must die before it.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "runtime/device_info.h"

namespace smokesvd {

class BufferPool;
class KernelCache;
class Kernel;
class TensorGuards;
struct KernelKey;

struct ContextOptions {
  // Empty: the best device (discrete > integrated > CPU); else an index or a name substring.
  // When empty, the environment variable SMOKESVD_DEVICE is used if set.
  std::string device;
  // Enable VK_LAYER_KHRONOS_validation. Also on when SMOKESVD_VALIDATION=1.
  bool validation = false;
  // With validation: the layer's synchronization validation too (missing barriers, hazards). Also on
  // when SMOKESVD_SYNC_VALIDATION=1.
  bool synchronizationValidation = false;
  // Move data through staging buffers even where memory is unified, as on a discrete GPU (tests that path).
  bool forceStaging = false;
  // Treat the device as lacking float32 atomic add, so that scattering kernels use their
  // compare-and-swap variants (tests that path); info().float32AtomicAdd then reads false.
  bool emulateFloatAtomics = false;
  // Test mode: every tensor starts NaN-filled and is followed by a guard region that its storage
  // bindings span; tensorGuards() reports guards a kernel wrote (runtime/tensor_guards.h).
  bool guardTensors = false;
  // Every Stream scans what each dispatch writes for NaN/Inf and throws at the first (runtime/finite_check.h).
  // Also on when SMOKESVD_CHECK=1.
  bool checkFinite = false;
};

class Context {
 public:
  explicit Context(ContextOptions options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Every device the loader reports, without creating a Context (for `smokesvd info`).
  static std::vector<DeviceInfo> listDevices(ContextOptions options = {});

  const DeviceInfo& info() const { return info_; }
  VkDevice device() const { return device_; }
  VkPhysicalDevice physicalDevice() const { return physicalDevice_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  VkCommandPool commandPool() const { return commandPool_; }
  BufferPool& buffers() { return *bufferPool_; }
  const Kernel& kernel(const KernelKey& key);
  // The names of the shaders built into kernels so far ("nn/conv_direct", ...), sorted, each once.
  std::vector<std::string> builtShaders() const;
  // The guards of a context created with guardTensors; nullptr otherwise.
  TensorGuards* tensorGuards() const { return tensorGuards_.get(); }
  bool validationEnabled() const { return validation_; }
  bool checkFinite() const { return checkFinite_; }
  // Whether tensor buffers are mapped and read/written with memcpy (unified memory) or staged.
  bool mappedBuffers() const { return info_.unifiedMemory && !forceStaging_; }
  PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet() const { return cmdPushDescriptorSet_; }

  // Messages the validation layer reported since the last call; emptied by the call.
  std::vector<std::string> takeValidationMessages();
  void reportValidationMessage(std::string message);
  // Messages of contexts already destroyed that nobody took, including those the layer raised while a
  // context was being destroyed (objects left alive, ...); emptied by the call. The command line checks
  // it before it exits, the test harness after the last test.
  static std::vector<std::string> takeUnreadValidationMessages();

  // Runs a one-off command buffer recorded by `record` and waits for it (uploads, downloads).
  template <typename Record>
  void runOnce(std::string_view what, Record&& record) {
    VkCommandBuffer commands = beginOneTime();
    record(commands);
    endOneTime(commands, what);
  }

 private:
  void release();
  VkCommandBuffer beginOneTime();
  void endOneTime(VkCommandBuffer commands, std::string_view what);

  bool validation_ = false;
  bool forceStaging_ = false;
  bool checkFinite_ = false;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
  DeviceInfo info_;
  VkDevice device_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool commandPool_ = VK_NULL_HANDLE;
  PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet_ = nullptr;
  std::unique_ptr<BufferPool> bufferPool_;
  std::unique_ptr<KernelCache> kernels_;
  std::unique_ptr<TensorGuards> tensorGuards_;
  std::mutex messagesMutex_;
  std::vector<std::string> validationMessages_;
};

}  // namespace smokesvd

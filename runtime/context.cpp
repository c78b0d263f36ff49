#include "runtime/context.h"

#include <cstdlib>
#include <cstring>
#include <utility>

#include "runtime/buffer.h"
#include "runtime/error.h"
#include "runtime/kernel.h"
#include "runtime/tensor_guards.h"

namespace smokesvd {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool envFlag(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr && std::strcmp(value, "0") != 0 && value[0] != '\0';
}

bool layerAvailable(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const VkLayerProperties& layer : layers)
    if (std::strcmp(layer.layerName, name) == 0) return true;
  return false;
}

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  static_cast<Context*>(user)->reportValidationMessage(data->pMessage ? data->pMessage : "(empty message)");
  return VK_FALSE;
}

VkDebugUtilsMessengerCreateInfoEXT messengerInfo(Context* context) {
  VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  info.pfnUserCallback = onValidationMessage;
  info.pUserData = context;
  return info;
}

struct InstanceHandle {
  VkInstance instance = VK_NULL_HANDLE;
  ~InstanceHandle() {
    if (instance) vkDestroyInstance(instance, nullptr);
  }
};

VkInstance createInstance(bool validation, bool synchronization, VkDebugUtilsMessengerCreateInfoEXT* messenger) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "smokesvd";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  if (validation) {
    if (!layerAvailable(kValidationLayer))
      throw Error("validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                  "(apt-get install vulkan-validationlayers)");
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.pNext = messenger;
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pNext = !validation ? nullptr : synchronization ? static_cast<const void*>(&features) : messenger;
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  vkCheck(vkCreateInstance(&info, nullptr, &instance), "creating the Vulkan instance");
  return instance;
}

// Messages of destroyed contexts that were never taken (Context::takeUnreadValidationMessages). Never
// destroyed, so that contexts in static storage can still add to it while the program exits.
struct UnreadMessages {
  std::mutex mutex;
  std::vector<std::string> messages;
};
UnreadMessages& unreadMessages() {
  static UnreadMessages* const unread = new UnreadMessages;
  return *unread;
}

std::string deviceRequest(const ContextOptions& options) {
  if (!options.device.empty()) return options.device;
  const char* env = std::getenv("SMOKESVD_DEVICE");
  return env ? env : "";
}

}  // namespace

std::vector<DeviceInfo> Context::listDevices(ContextOptions) {
  InstanceHandle handle;
  handle.instance = createInstance(false, false, nullptr);
  return queryDevices(handle.instance);
}

Context::Context(ContextOptions options)
    : validation_(options.validation || envFlag("SMOKESVD_VALIDATION")),
      forceStaging_(options.forceStaging),
      checkFinite_(options.checkFinite || envFlag("SMOKESVD_CHECK")) {
  VkDebugUtilsMessengerCreateInfoEXT messenger = messengerInfo(this);
  const bool synchronization = options.synchronizationValidation || envFlag("SMOKESVD_SYNC_VALIDATION");
  instance_ = createInstance(validation_, synchronization, &messenger);
  try {
    if (validation_) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      vkCheck(create(instance_, &messenger, nullptr, &messenger_), "creating the validation messenger");
    }
    std::vector<DeviceInfo> devices = queryDevices(instance_);
    info_ = chooseDevice(devices, deviceRequest(options));
    if (options.emulateFloatAtomics) info_.float32AtomicAdd = false;
    if (!info_.pushDescriptor)
      throw Error("device '" + info_.name + "' lacks VK_KHR_push_descriptor, which smokesvd requires");

    uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance_, &count, nullptr);
    std::vector<VkPhysicalDevice> handles(count);
    vkEnumeratePhysicalDevices(instance_, &count, handles.data());
    physicalDevice_ = handles[info_.index];

    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice_, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice_, &familyCount, families.data());
    int chosen = -1;
    for (uint32_t f = 0; f < familyCount; ++f) {
      const bool compute = families[f].queueFlags & VK_QUEUE_COMPUTE_BIT;
      if (compute && (chosen < 0 || (families[f].timestampValidBits > 0 && families[chosen].timestampValidBits == 0)))
        chosen = static_cast<int>(f);
    }
    if (chosen < 0) throw Error("device '" + info_.name + "' has no compute queue");
    queueFamily_ = static_cast<uint32_t>(chosen);

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = queueFamily_;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    std::vector<const char*> extensions = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomicFloat{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
    VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    if (info_.float32AtomicAdd) {
      extensions.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
      atomicFloat.shaderBufferFloat32AtomicAdd = VK_TRUE;
      features12.pNext = &atomicFloat;
    }
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features12};
    VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    deviceInfo.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    deviceInfo.ppEnabledExtensionNames = extensions.data();
    vkCheck(vkCreateDevice(physicalDevice_, &deviceInfo, nullptr, &device_), "creating device '" + info_.name + "'");
    vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
    cmdPushDescriptorSet_ = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
        vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = queueFamily_;
    vkCheck(vkCreateCommandPool(device_, &poolInfo, nullptr, &commandPool_), "creating a command pool");
    bufferPool_ = std::make_unique<BufferPool>(*this);
    kernels_ = std::make_unique<KernelCache>(*this);
    if (options.guardTensors) tensorGuards_ = std::make_unique<TensorGuards>();
  } catch (...) {
    release();
    throw;
  }
}

Context::~Context() { release(); }

void Context::release() {
  kernels_.reset();
  bufferPool_.reset();
  if (commandPool_) vkDestroyCommandPool(device_, commandPool_, nullptr);
  if (device_) vkDestroyDevice(device_, nullptr);
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  commandPool_ = VK_NULL_HANDLE;
  device_ = VK_NULL_HANDLE;
  messenger_ = VK_NULL_HANDLE;
  instance_ = VK_NULL_HANDLE;
  std::vector<std::string> untaken = takeValidationMessages();
  UnreadMessages& unread = unreadMessages();
  std::lock_guard lock(unread.mutex);
  unread.messages.insert(unread.messages.end(), untaken.begin(), untaken.end());
}

std::vector<std::string> Context::takeUnreadValidationMessages() {
  UnreadMessages& unread = unreadMessages();
  std::lock_guard lock(unread.mutex);
  return std::exchange(unread.messages, {});
}

const Kernel& Context::kernel(const KernelKey& key) { return kernels_->get(key); }

std::vector<std::string> Context::builtShaders() const { return kernels_->shaders(); }

std::vector<std::string> Context::takeValidationMessages() {
  std::lock_guard lock(messagesMutex_);
  return std::exchange(validationMessages_, {});
}

void Context::reportValidationMessage(std::string message) {
  std::lock_guard lock(messagesMutex_);
  validationMessages_.push_back(std::move(message));
}

VkCommandBuffer Context::beginOneTime() {
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = commandPool_;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VkCommandBuffer commands = VK_NULL_HANDLE;
  vkCheck(vkAllocateCommandBuffers(device_, &allocate, &commands), "allocating a command buffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vkBeginCommandBuffer(commands, &begin);
  return commands;
}

void Context::endOneTime(VkCommandBuffer commands, std::string_view what) {
  struct Release {
    Context* context;
    VkCommandBuffer commands;
    ~Release() { vkFreeCommandBuffers(context->device_, context->commandPool_, 1, &commands); }
  } release{this, commands};
  vkCheck(vkEndCommandBuffer(commands), std::string(what) + ": ending the command buffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  vkCheck(vkQueueSubmit(queue_, 1, &submit, VK_NULL_HANDLE), std::string(what) + ": submitting");
  vkCheck(vkQueueWaitIdle(queue_), std::string(what) + ": waiting for the device");
}

}  // namespace smokesvd

#include "runtime/device_info.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "runtime/error.h"

namespace smokesvd {
namespace {

bool hasExtension(const std::vector<VkExtensionProperties>& extensions, const char* name) {
  return std::any_of(extensions.begin(), extensions.end(),
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

DeviceInfo describe(VkPhysicalDevice device, uint32_t index) {
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES, &subgroup};
  VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
  vkGetPhysicalDeviceProperties2(device, &properties);
  const VkPhysicalDeviceLimits& limits = properties.properties.limits;

  uint32_t extensionCount = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &extensionCount, nullptr);
  std::vector<VkExtensionProperties> extensions(extensionCount);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &extensionCount, extensions.data());

  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomicFloat{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  const bool hasAtomicFloat = hasExtension(extensions, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
  if (hasAtomicFloat) features12.pNext = &atomicFloat;
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features12};
  vkGetPhysicalDeviceFeatures2(device, &features);

  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(device, &memory);

  uint32_t familyCount = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &familyCount, nullptr);
  std::vector<VkQueueFamilyProperties> families(familyCount);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &familyCount, families.data());

  DeviceInfo info;
  info.index = index;
  info.name = properties.properties.deviceName;
  info.type = properties.properties.deviceType;
  info.apiVersion = properties.properties.apiVersion;
  info.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  info.maxStorageBufferRange = limits.maxStorageBufferRange;
  info.maxTexelBufferElements = limits.maxTexelBufferElements;
  info.maxSharedMemoryBytes = limits.maxComputeSharedMemorySize;
  info.maxWorkgroupInvocations = limits.maxComputeWorkGroupInvocations;
  for (int axis = 0; axis < 3; ++axis) info.maxWorkgroupCount[axis] = limits.maxComputeWorkGroupCount[axis];
  info.maxPushConstantBytes = limits.maxPushConstantsSize;
  info.subgroupSize = subgroup.subgroupSize;
  for (uint32_t heap = 0; heap < memory.memoryHeapCount; ++heap) {
    if (memory.memoryHeaps[heap].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      info.deviceLocalBytes = std::max<uint64_t>(info.deviceLocalBytes, memory.memoryHeaps[heap].size);
  }
  info.unifiedMemory =
      info.type == VK_PHYSICAL_DEVICE_TYPE_CPU || info.type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU;
  info.float16 = features12.shaderFloat16 == VK_TRUE;
  info.float32AtomicAdd = hasAtomicFloat && atomicFloat.shaderBufferFloat32AtomicAdd == VK_TRUE;
  info.pushDescriptor = hasExtension(extensions, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
  for (const VkQueueFamilyProperties& family : families) {
    if ((family.queueFlags & VK_QUEUE_COMPUTE_BIT) && family.timestampValidBits > 0) info.timestamps = true;
  }
  info.timestampPeriodNs = limits.timestampPeriod;
  if (info.type == VK_PHYSICAL_DEVICE_TYPE_CPU) info.hostThreads = cpuDeviceThreads();
  return info;
}

}  // namespace

uint32_t cpuDeviceThreads() {
  if (const char* value = std::getenv("LP_NUM_THREADS"); value != nullptr) {
    char* end = nullptr;
    const long threads = std::strtol(value, &end, 10);
    if (end != value && *end == '\0' && threads > 0) return static_cast<uint32_t>(threads);
  }
  return std::max(std::thread::hardware_concurrency(), 1u);
}

std::string DeviceInfo::typeName() const {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

uint32_t DeviceInfo::reductionWorkgroup() const {
  return std::clamp(std::bit_floor(std::max(subgroupSize, 1u)), 8u, 256u);
}

uint64_t DeviceInfo::maxTensorBytes() const {
  return std::min<uint64_t>(maxStorageBufferRange, uint64_t{4} * maxTexelBufferElements);
}

int DeviceInfo::preferenceRank() const {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

std::vector<DeviceInfo> queryDevices(VkInstance instance) {
  uint32_t count = 0;
  vkCheck(vkEnumeratePhysicalDevices(instance, &count, nullptr), "listing Vulkan devices");
  std::vector<VkPhysicalDevice> handles(count);
  vkCheck(vkEnumeratePhysicalDevices(instance, &count, handles.data()), "listing Vulkan devices");
  std::vector<DeviceInfo> devices;
  for (uint32_t i = 0; i < count; ++i) devices.push_back(describe(handles[i], i));
  return devices;
}

const DeviceInfo& chooseDevice(const std::vector<DeviceInfo>& devices, const std::string& request) {
  if (devices.empty())
    throw Error("no Vulkan device found: install a GPU driver or Mesa's lavapipe (apt-get install mesa-vulkan-drivers)");
  if (request.empty()) {
    return *std::min_element(devices.begin(), devices.end(), [](const DeviceInfo& a, const DeviceInfo& b) {
      return a.preferenceRank() < b.preferenceRank();
    });
  }
  const bool isIndex = std::all_of(request.begin(), request.end(), [](unsigned char c) { return std::isdigit(c); });
  for (const DeviceInfo& device : devices) {
    if (isIndex ? std::to_string(device.index) == request
                : lower(device.name).find(lower(request)) != std::string::npos)
      return device;
  }
  std::string available;
  for (const DeviceInfo& device : devices)
    available += (available.empty() ? "" : ", ") + std::to_string(device.index) + " '" + device.name + "'";
  throw Error("device '" + request + "' (from --device or SMOKESVD_DEVICE) matches no Vulkan device; available: " +
              available);
}

}  // namespace smokesvd

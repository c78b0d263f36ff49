// What smokesvd needs to know about a Vulkan physical device, read once at start-up.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace smokesvd {

// Loop iterations one shader invocation may run in all, on every device: llvmpipe (lavapipe) ends the
// loops of an invocation after 65535 iterations, counted over every loop of it together, and silently
// (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS). Kernels whose invocations loop over a share of the work that
// grows with the problem split it so that no share passes this budget (half the limit; docs/runtime.md).
constexpr uint64_t kLoopIterationBudget = 32768;

struct DeviceInfo {
  uint32_t index = 0;                 // position in vkEnumeratePhysicalDevices
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t apiVersion = 0;
  std::string driver;                 // driver name and info, e.g. "llvmpipe Mesa 22.3.6"
  uint64_t maxStorageBufferRange = 0; // bytes one storage-buffer binding may span
  uint32_t maxTexelBufferElements = 0;
  uint32_t maxSharedMemoryBytes = 0;
  uint32_t maxWorkgroupInvocations = 0;
  std::array<uint32_t, 3> maxWorkgroupCount{};
  uint32_t maxPushConstantBytes = 0;
  uint32_t subgroupSize = 0;
  uint64_t deviceLocalBytes = 0;      // size of the largest device-local heap
  bool unifiedMemory = false;         // CPU or integrated: buffers live in host-visible memory
  bool float16 = false;               // shaderFloat16
  bool float32AtomicAdd = false;      // VK_EXT_shader_atomic_float on storage buffers
  bool pushDescriptor = false;        // VK_KHR_push_descriptor (required)
  bool timestamps = false;            // compute queue can write timestamps
  float timestampPeriodNs = 0;        // nanoseconds per timestamp tick
  // CPU devices: how many host threads run its workgroups. lavapipe starts one per hardware thread unless
  // LP_NUM_THREADS says otherwise, and that is what this reads; 0 for every other device type.
  uint32_t hostThreads = 0;

  std::string typeName() const;
  // Workgroup size for kernels that reduce through a shared-memory tree: one subgroup, rounded down to
  // a power of two and kept in [8, 256]. On CPU devices each barrier between the subgroups of a
  // workgroup is a context switch; with one subgroup GroupNorm ran 1.6x faster on lavapipe than with
  // 64 invocations (docs/runtime.md). GPUs run such workgroups as one full warp or wave.
  uint32_t reductionWorkgroup() const;
  // The largest tensor the runtime accepts, in bytes: one storage-buffer binding must span it (writes) and
  // a float texel view must reach every element (reads), so min(maxStorageBufferRange,
  // 4 · maxTexelBufferElements): 128 MiB on lavapipe, 512 MiB on NVIDIA GPUs.
  uint64_t maxTensorBytes() const;
  // Lower is preferred: discrete GPU, integrated GPU, virtual GPU, CPU, other.
  int preferenceRank() const;
};

// The threads a CPU Vulkan device runs workgroups on (DeviceInfo::hostThreads): LP_NUM_THREADS where it is a
// positive number (lavapipe reads it), the host's hardware threads otherwise; at least 1.
uint32_t cpuDeviceThreads();

// Reads every physical device the instance sees.
std::vector<DeviceInfo> queryDevices(VkInstance instance);

// Chooses a device: `request` is empty (best by preferenceRank), a decimal index, or a case-insensitive
// substring of the device name. Throws Error naming the request and listing the devices otherwise.
const DeviceInfo& chooseDevice(const std::vector<DeviceInfo>& devices, const std::string& request);

}  // namespace smokesvd

// Compute pipelines. A Kernel is one (shader, workgroup size, specialization constants) combination,
// built once from the embedded SPIR-V and cached by the Context. Its bindings are reflected from the
// SPIR-V, so the host never restates them.
//
// Shader contract: `layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;`,
// kernel-specific specialization constants from constant_id 3 on, bindings in set 0 numbered 0..n-1,
// and at most 128 bytes of push constants.
#pragma once

#include <array>
#include <compare>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "runtime/spirv_reflect.h"

namespace smokesvd {

class Context;

struct KernelKey {
  std::string shader;                         // e.g. "tensor/fill"
  std::array<uint32_t, 3> workgroup{64, 1, 1};
  std::vector<int32_t> constants;             // values for constant_id 3, 4, ...
  auto operator<=>(const KernelKey&) const = default;
};

class Kernel {
 public:
  Kernel(Context& context, KernelKey key);
  ~Kernel();
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;

  const KernelKey& key() const { return key_; }
  const std::vector<BindingInfo>& bindings() const { return interface_.bindings; }
  bool hasPushConstants() const { return interface_.hasPushConstants; }
  uint32_t pushConstantCapacity() const { return pushBytes_; }
  VkPipeline pipeline() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }

 private:
  void build();
  void destroy();

  Context& context_;
  KernelKey key_;
  ShaderInterface interface_;
  uint32_t pushBytes_ = 0;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

class KernelCache {
 public:
  explicit KernelCache(Context& context) : context_(context) {}
  const Kernel& get(const KernelKey& key);
  // The shader of every kernel built so far, sorted, each once.
  std::vector<std::string> shaders() const;

 private:
  Context& context_;
  mutable std::mutex mutex_;
  std::map<KernelKey, std::unique_ptr<Kernel>> kernels_;
};

}  // namespace smokesvd

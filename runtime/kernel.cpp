#include "runtime/kernel.h"

#include <algorithm>

#include "runtime/context.h"
#include "runtime/embedded_shaders.h"
#include "runtime/error.h"

namespace smokesvd {
namespace {

constexpr uint32_t kPushConstantBytes = 128;  // the minimum every Vulkan device offers

std::span<const uint32_t> findShader(const std::string& name) {
  const auto& shaders = embeddedShaders();
  auto found = shaders.find(name);
  if (found == shaders.end()) throw Error("no shader named '" + name + "' is embedded in this build");
  return found->second;
}

}  // namespace

Kernel::Kernel(Context& context, KernelKey key) : context_(context), key_(std::move(key)) {
  try {
    build();
  } catch (...) {
    destroy();
    throw;
  }
}

void Kernel::build() {
  Context& context = context_;
  const std::span<const uint32_t> spirv = findShader(key_.shader);
  interface_ = reflectShader(spirv, key_.shader);
  const auto& ids = interface_.specializationIds;
  if (std::find(ids.begin(), ids.end(), 0u) == ids.end())
    throw Error("shader '" + key_.shader + "' must declare layout(local_size_x_id = 0, ...) in");
  const DeviceInfo& info = context.info();
  const uint64_t invocations = uint64_t{key_.workgroup[0]} * key_.workgroup[1] * key_.workgroup[2];
  if (invocations == 0 || invocations > info.maxWorkgroupInvocations)
    throw Error("kernel '" + key_.shader + "': workgroup of " + std::to_string(invocations) +
                " invocations; the device allows 1 to " + std::to_string(info.maxWorkgroupInvocations));
  pushBytes_ = interface_.hasPushConstants ? kPushConstantBytes : 0;
  VkDevice device = context.device();
  const std::string doing = "building kernel '" + key_.shader + "'";

  VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  moduleInfo.codeSize = spirv.size_bytes();
  moduleInfo.pCode = spirv.data();
  vkCheck(vkCreateShaderModule(device, &moduleInfo, nullptr, &module_), doing);

  std::vector<VkDescriptorSetLayoutBinding> layoutBindings;
  for (const BindingInfo& binding : interface_.bindings) {
    VkDescriptorSetLayoutBinding entry{};
    entry.binding = binding.binding;
    entry.descriptorType = binding.kind == BindingKind::StorageBuffer ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER
                                                                      : VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    entry.descriptorCount = 1;
    entry.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    layoutBindings.push_back(entry);
  }
  VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  setInfo.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  setInfo.bindingCount = static_cast<uint32_t>(layoutBindings.size());
  setInfo.pBindings = layoutBindings.data();
  vkCheck(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &setLayout_), doing);

  VkPushConstantRange pushRange{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushBytes_};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &setLayout_;
  layoutInfo.pushConstantRangeCount = pushBytes_ ? 1 : 0;
  layoutInfo.pPushConstantRanges = &pushRange;
  vkCheck(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &layout_), doing);

  std::vector<uint32_t> values(key_.workgroup.begin(), key_.workgroup.end());
  for (int32_t constant : key_.constants) values.push_back(static_cast<uint32_t>(constant));
  std::vector<VkSpecializationMapEntry> entries;
  for (uint32_t id = 0; id < values.size(); ++id) {
    if (std::find(ids.begin(), ids.end(), id) != ids.end())
      entries.push_back({id, static_cast<uint32_t>(id * sizeof(uint32_t)), sizeof(uint32_t)});
    else if (id >= 3)
      throw Error("kernel '" + key_.shader + "': constant_id " + std::to_string(id) + " is not declared by the shader");
  }
  VkSpecializationInfo specialization{};
  specialization.mapEntryCount = static_cast<uint32_t>(entries.size());
  specialization.pMapEntries = entries.data();
  specialization.dataSize = values.size() * sizeof(uint32_t);
  specialization.pData = values.data();

  VkComputePipelineCreateInfo pipelineInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  pipelineInfo.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipelineInfo.stage.module = module_;
  pipelineInfo.stage.pName = "main";
  pipelineInfo.stage.pSpecializationInfo = &specialization;
  pipelineInfo.layout = layout_;
  vkCheck(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipelineInfo, nullptr, &pipeline_), doing);
}

Kernel::~Kernel() { destroy(); }

void Kernel::destroy() {
  VkDevice device = context_.device();
  if (pipeline_) vkDestroyPipeline(device, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(device, layout_, nullptr);
  if (setLayout_) vkDestroyDescriptorSetLayout(device, setLayout_, nullptr);
  if (module_) vkDestroyShaderModule(device, module_, nullptr);
}

const Kernel& KernelCache::get(const KernelKey& key) {
  std::lock_guard lock(mutex_);
  std::unique_ptr<Kernel>& kernel = kernels_[key];
  if (!kernel) kernel = std::make_unique<Kernel>(context_, key);
  return *kernel;
}

std::vector<std::string> KernelCache::shaders() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> names;
  for (const auto& [key, kernel] : kernels_)
    if (names.empty() || names.back() != key.shader) names.push_back(key.shader);
  return names;
}

}  // namespace smokesvd

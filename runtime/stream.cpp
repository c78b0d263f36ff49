#include "runtime/stream.h"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd {

Stream::Stream(Context& context, StreamOptions options) : context_(context), options_(options) {
  VkDevice device = context.device();
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = context.commandPool();
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  vkCheck(vkAllocateCommandBuffers(device, &allocate, &commands_), "allocating a command stream");
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkResult result = vkCreateFence(device, &fenceInfo, nullptr, &fence_);
  if (result == VK_SUCCESS && context.info().timestamps) {
    VkQueryPoolCreateInfo queryInfo{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    queryInfo.queryType = VK_QUERY_TYPE_TIMESTAMP;
    queryInfo.queryCount = 2 * options_.maxRegions;
    result = vkCreateQueryPool(device, &queryInfo, nullptr, &queries_);
  }
  if (result != VK_SUCCESS) {
    release();
    throw VulkanError(result, "creating a command stream");
  }
}

Stream::~Stream() { release(); }

void Stream::release() {
  VkDevice device = context_.device();
  if (queries_) vkDestroyQueryPool(device, queries_, nullptr);
  if (fence_) vkDestroyFence(device, fence_, nullptr);
  if (commands_) vkFreeCommandBuffers(device, context_.commandPool(), 1, &commands_);
  queries_ = VK_NULL_HANDLE;
  fence_ = VK_NULL_HANDLE;
  commands_ = VK_NULL_HANDLE;
}

const Kernel& Stream::kernel(const std::string& shader, std::array<uint32_t, 3> workgroup,
                             std::vector<int32_t> constants) const {
  return context_.kernel(KernelKey{shader, workgroup, std::move(constants)});
}

void Stream::begin() {
  if (ended_) throw Error("command stream was already submitted; call reset() before recording more");
  if (recording_) return;
  VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  vkCheck(vkBeginCommandBuffer(commands_, &info), "beginning a command stream");
  if (queries_) vkCmdResetQueryPool(commands_, queries_, 0, 2 * options_.maxRegions);
  recording_ = true;
}

void Stream::barrier() {
  VkMemoryBarrier memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  memory.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  memory.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                         VK_ACCESS_TRANSFER_WRITE_BIT;
  const VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  vkCmdPipelineBarrier(commands_, stages, stages, 0, 1, &memory, 0, nullptr, 0, nullptr);
  ++barriers_;
  readSinceBarrier_.clear();
  writtenSinceBarrier_.clear();
}

void Stream::access(const Buffer& buffer, bool reads, bool writes) {
  const VkBuffer handle = buffer.handle();
  const bool readAfterWrite = reads && writtenSinceBarrier_.count(handle);
  const bool writeAfterAccess = writes && (writtenSinceBarrier_.count(handle) || readSinceBarrier_.count(handle));
  if (readAfterWrite || writeAfterAccess) barrier();
}

void Stream::dispatch(const Kernel& kernel, std::span<const Arg> args, const void* push, uint32_t pushBytes,
                      std::array<uint32_t, 3> groups) {
  const std::string& name = kernel.key().shader;
  const std::vector<BindingInfo>& bindings = kernel.bindings();
  if (args.size() != bindings.size())
    throw Error("kernel '" + name + "' has " + std::to_string(bindings.size()) + " bindings but was given " +
                std::to_string(args.size()) + " arguments");
  if (pushBytes > kernel.pushConstantCapacity())
    throw Error("kernel '" + name + "': " + std::to_string(pushBytes) + " bytes of push constants, at most " +
                std::to_string(kernel.pushConstantCapacity()));
  const DeviceInfo& info = context_.info();
  for (int axis = 0; axis < 3; ++axis) {
    if (groups[axis] > info.maxWorkgroupCount[axis])
      throw Error("kernel '" + name + "': " + std::to_string(groups[axis]) + " workgroups along axis " +
                  std::to_string(axis) + ", the device allows " + std::to_string(info.maxWorkgroupCount[axis]));
  }
  if (groups[0] == 0 || groups[1] == 0 || groups[2] == 0) return;
  begin();

  // Barrier decisions first (a barrier clears the tracking sets), then this dispatch's own accesses.
  for (std::size_t i = 0; i < args.size(); ++i) access(*args[i].buffer, bindings[i].reads, bindings[i].writes);

  std::vector<VkWriteDescriptorSet> writes(args.size());
  std::vector<VkDescriptorBufferInfo> bufferInfos(args.size());
  std::vector<VkBufferView> views(args.size());
  for (std::size_t i = 0; i < args.size(); ++i) {
    const Arg& arg = args[i];
    VkWriteDescriptorSet& write = writes[i];
    write = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstBinding = static_cast<uint32_t>(i);
    write.descriptorCount = 1;
    if (bindings[i].kind == BindingKind::StorageBuffer) {
      const uint64_t padded = (std::max<uint64_t>(arg.bytes, 4) + 15) / 16 * 16;
      bufferInfos[i] = {arg.buffer->handle(), 0,
                        std::min<uint64_t>({padded, arg.buffer->capacity(), info.maxStorageBufferRange})};
      write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      write.pBufferInfo = &bufferInfos[i];
    } else {
      views[i] = arg.buffer->view(arg.format);
      write.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
      write.pTexelBufferView = &views[i];
    }
    if (bindings[i].reads) readSinceBarrier_.insert(arg.buffer->handle());
    if (bindings[i].writes) writtenSinceBarrier_.insert(arg.buffer->handle());
    keepAlive_.push_back(arg.buffer);
  }

  if (options_.profileDispatches) beginRegion(name);
  vkCmdBindPipeline(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.pipeline());
  if (!writes.empty())
    context_.cmdPushDescriptorSet()(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.layout(), 0,
                    static_cast<uint32_t>(writes.size()), writes.data());
  if (pushBytes > 0)
    vkCmdPushConstants(commands_, kernel.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, pushBytes, push);
  vkCmdDispatch(commands_, groups[0], groups[1], groups[2]);
  if (options_.profileDispatches) endRegion();
  ++dispatches_;
}

void Stream::dispatchFlat(const Kernel& kernel, std::span<const Arg> args, const void* push, uint32_t pushBytes,
                          uint64_t invocations) {
  const std::array<uint32_t, 3>& workgroup = kernel.key().workgroup;
  if (workgroup[1] != 1 || workgroup[2] != 1)
    throw Error("kernel '" + kernel.key().shader + "': dispatchFlat needs a workgroup of shape [x, 1, 1]");
  const uint64_t groups = (invocations + workgroup[0] - 1) / workgroup[0];
  const uint64_t width = std::min<uint64_t>(groups, 65535);
  const uint64_t height = width == 0 ? 0 : (groups + width - 1) / width;
  dispatch(kernel, args, push, pushBytes,
           {static_cast<uint32_t>(width), static_cast<uint32_t>(std::max<uint64_t>(height, width ? 1 : 0)), 1});
}

void Stream::copy(const Tensor& source, const Tensor& destination) {
  if (source.numel() != destination.numel())
    throw Error("copy from tensor " + toString(source.shape()) + " to " + toString(destination.shape()) +
                ": element counts differ");
  if (source.numel() == 0) return;
  begin();
  access(source.buffer(), true, false);
  access(destination.buffer(), false, true);
  VkBufferCopy region{0, 0, source.bytes()};
  vkCmdCopyBuffer(commands_, source.buffer().handle(), destination.buffer().handle(), 1, &region);
  readSinceBarrier_.insert(source.buffer().handle());
  writtenSinceBarrier_.insert(destination.buffer().handle());
  keepAlive_.push_back(source.sharedBuffer());
  keepAlive_.push_back(destination.sharedBuffer());
}

void Stream::fillZero(const Tensor& tensor) {
  if (tensor.numel() == 0) return;
  begin();
  access(tensor.buffer(), false, true);
  vkCmdFillBuffer(commands_, tensor.buffer().handle(), 0, tensor.bytes(), 0);
  writtenSinceBarrier_.insert(tensor.buffer().handle());
  keepAlive_.push_back(tensor.sharedBuffer());
}

void Stream::beginRegion(std::string name) {
  if (!queries_) return;
  begin();
  if (queriesUsed_ + 2 > 2 * options_.maxRegions)
    throw Error("command stream: more than " + std::to_string(options_.maxRegions) + " timed regions");
  regions_.push_back({std::move(name), queriesUsed_, 0});
  openRegions_.push_back(regions_.size() - 1);
  vkCmdWriteTimestamp(commands_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, queriesUsed_++);
}

void Stream::endRegion() {
  if (!queries_) return;
  if (openRegions_.empty()) throw Error("command stream: endRegion() without beginRegion()");
  Region& region = regions_[openRegions_.back()];
  openRegions_.pop_back();
  region.endQuery = queriesUsed_;
  vkCmdWriteTimestamp(commands_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, queriesUsed_++);
}

void Stream::submit() {
  if (!openRegions_.empty()) throw Error("command stream: region '" + regions_[openRegions_.back()].name + "' is still open");
  if (!recording_) return;  // nothing recorded
  if (!ended_) {
    vkCheck(vkEndCommandBuffer(commands_), "ending a command stream");
    ended_ = true;
  }
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands_;
  const std::string doing = "running a command stream of " + std::to_string(dispatches_) + " dispatches";
  vkCheck(vkQueueSubmit(context_.queue(), 1, &submit, fence_), doing);
  vkCheck(vkWaitForFences(context_.device(), 1, &fence_, VK_TRUE, std::numeric_limits<uint64_t>::max()), doing);
  vkCheck(vkResetFences(context_.device(), 1, &fence_), doing);

  times_.clear();
  if (queries_ && queriesUsed_ > 0) {
    std::vector<uint64_t> stamps(queriesUsed_);
    vkCheck(vkGetQueryPoolResults(context_.device(), queries_, 0, queriesUsed_, stamps.size() * sizeof(uint64_t),
                                  stamps.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
            "reading timestamps");
    for (const Region& region : regions_) {
      const double ticks = static_cast<double>(stamps[region.endQuery] - stamps[region.beginQuery]);
      times_.push_back({region.name, ticks * context_.info().timestampPeriodNs});
    }
  }
}

void Stream::reset() {
  if (recording_) vkCheck(vkResetCommandBuffer(commands_, 0), "resetting a command stream");
  recording_ = false;
  ended_ = false;
  dispatches_ = 0;
  barriers_ = 0;
  readSinceBarrier_.clear();
  writtenSinceBarrier_.clear();
  keepAlive_.clear();
  regions_.clear();
  openRegions_.clear();
  queriesUsed_ = 0;
  times_.clear();
}

}  // namespace smokesvd

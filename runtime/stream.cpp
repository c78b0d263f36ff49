#include "runtime/stream.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "runtime/context.h"
#include "runtime/error.h"
#include "runtime/finite_check.h"

namespace smokesvd {
namespace {

// Workgroups for `invocations` items of a flat dispatch: a 2D grid, as flat_index() in index.glsl expects.
std::array<uint32_t, 3> flatGroups(uint64_t invocations, uint32_t workgroupX) {
  const uint64_t groups = (invocations + workgroupX - 1) / workgroupX;
  const uint64_t width = std::min<uint64_t>(groups, 65535);
  const uint64_t height = width == 0 ? 0 : (groups + width - 1) / width;
  return {static_cast<uint32_t>(width), static_cast<uint32_t>(std::max<uint64_t>(height, width ? 1 : 0)), 1};
}

// RegionTime::detail of a profiled dispatch: "groups 3x112x1; constants 3,3,3,1; push 16,70992".
std::string dispatchDetail(const KernelKey& key, const std::array<uint32_t, 3>& groups, const void* push,
                           uint32_t pushBytes) {
  std::string detail = "groups " + std::to_string(groups[0]) + "x" + std::to_string(groups[1]) + "x" + std::to_string(groups[2]);
  auto list = [&detail](const char* label, const auto& values) {
    if (values.empty()) return;
    detail.append("; ").append(label).append(" ");
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (i > 0) detail.push_back(',');
      detail.append(std::to_string(values[i]));
    }
  };
  list("constants", key.constants);
  std::vector<int32_t> words(pushBytes / sizeof(int32_t));
  if (!words.empty()) std::memcpy(words.data(), push, words.size() * sizeof(int32_t));
  list("push", words);
  return detail;
}

// The floats of an argument the finite check scans: the tensor's elements (not the padding or guard its
// binding may span), or every float of a raw buffer argument.
uint64_t scannedElements(const Arg& arg) {
  return arg.shape ? static_cast<uint64_t>(numElements(*arg.shape)) : arg.bytes / sizeof(float);
}

// Whether the finite check scans what a dispatch writes to this argument.
bool scanned(const Arg& arg, const BindingInfo& binding) {
  return binding.writes && binding.finiteFloats && scannedElements(arg) > 0;
}

}  // namespace

Stream::Stream(Context& context, StreamOptions options)
    : context_(context), options_(options), memory_(options.reuseBuffers) {
  if (options_.checkFinite || context.checkFinite()) check_ = std::make_unique<FiniteCheck>(context);
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

void Stream::useBuffers(std::span<const Arg> args, const std::vector<BindingInfo>& bindings) {
  struct Use {
    Buffer* buffer;
    bool reads, writes;
  };
  std::vector<Use> uses;
  for (std::size_t i = 0; i < args.size(); ++i) {
    Buffer* buffer = args[i].buffer.get();
    auto same = std::find_if(uses.begin(), uses.end(), [&](const Use& use) { return use.buffer == buffer; });
    if (same == uses.end()) {
      uses.push_back({buffer, bindings[i].reads, bindings[i].writes});
    } else {
      same->reads = same->reads || bindings[i].reads;
      same->writes = same->writes || bindings[i].writes;
    }
  }
  for (const Use& use : uses) hold(*use.buffer, use.reads, use.writes);
}

void Stream::hold(Buffer& buffer, bool reads, bool writes) {
  memory_.use(buffer, reads, writes, [this](VkBuffer handle) {
    return readSinceBarrier_.count(handle) > 0 || writtenSinceBarrier_.count(handle) > 0;
  });
}

void Stream::access(const Buffer& buffer, bool reads, bool writes) {
  if (writes && buffer.constant())
    throw Error("a recorded command would write a constant tensor (frozen weights, Tensor::markConstant): only the "
                "host may write it");
  if (writes) ++writesRecorded_[&buffer];
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
  for (std::size_t i = 0; i < args.size(); ++i)
    if (bindings[i].writes && args[i].buffer->constant())
      throw Error("kernel '" + name + "' would write its binding '" + bindings[i].name +
                  "', a constant tensor (frozen weights, Tensor::markConstant): only the host may write it");
  if (groups[0] == 0 || groups[1] == 0 || groups[2] == 0) return;
  begin();
  useBuffers(args, bindings);
  const std::vector<Buffer*> snapshots = check_ ? snapshotWrites(args, bindings) : std::vector<Buffer*>{};

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
  }

  if (options_.profileDispatches) beginRegion(name, dispatchDetail(kernel.key(), groups, push, pushBytes));
  vkCmdBindPipeline(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.pipeline());
  if (!writes.empty())
    context_.cmdPushDescriptorSet()(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.layout(), 0,
                    static_cast<uint32_t>(writes.size()), writes.data());
  if (pushBytes > 0)
    vkCmdPushConstants(commands_, kernel.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, pushBytes, push);
  vkCmdDispatch(commands_, groups[0], groups[1], groups[2]);
  if (options_.profileDispatches) endRegion();
  ++dispatches_;
  if (check_) scanWrites(name, args, bindings, snapshots);
}

std::vector<Buffer*> Stream::snapshotWrites(std::span<const Arg> args, const std::vector<BindingInfo>& bindings) {
  std::vector<Buffer*> snapshots(args.size(), nullptr);
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (!scanned(args[i], bindings[i])) continue;
    const uint64_t bytes = scannedElements(args[i]) * sizeof(float);
    Buffer& snapshot = check_->snapshot(i, bytes);
    access(*args[i].buffer, true, false);
    access(snapshot, false, true);
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(commands_, args[i].buffer->handle(), snapshot.handle(), 1, &region);
    readSinceBarrier_.insert(args[i].buffer->handle());
    writtenSinceBarrier_.insert(snapshot.handle());
    snapshots[i] = &snapshot;
  }
  return snapshots;
}

void Stream::scanWrites(const std::string& shader, std::span<const Arg> args,
                        const std::vector<BindingInfo>& bindings, const std::vector<Buffer*>& snapshots) {
  const Kernel& scan = kernel(FiniteCheck::kShader);
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (!snapshots[i]) continue;
    const Arg& arg = args[i];
    const uint64_t elements = scannedElements(arg);
    const FiniteCheck::Slot slot =
        check_->add(shader, dispatches_, bindings[i], elements, arg.shape ? *arg.shape : Shape{});
    if (slot.resetChunk) {
      vkCmdFillBuffer(commands_, slot.report, 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
      barrier();
    }
    access(*arg.buffer, true, false);
    access(*snapshots[i], true, false);
    VkBufferView views[2] = {arg.buffer->view(TexelFormat::Float4), snapshots[i]->view(TexelFormat::Float4)};
    VkDescriptorBufferInfo report{slot.report, slot.offset, slot.range};
    VkWriteDescriptorSet writes[3];
    for (uint32_t binding = 0; binding < 3; ++binding) {
      writes[binding] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
      writes[binding].dstBinding = binding;
      writes[binding].descriptorCount = 1;
      writes[binding].descriptorType =
          binding < 2 ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      if (binding < 2) writes[binding].pTexelBufferView = &views[binding];
    }
    writes[2].pBufferInfo = &report;
    const uint32_t n = static_cast<uint32_t>(elements);
    const std::array<uint32_t, 3> groups = flatGroups((elements + 3) / 4, scan.key().workgroup[0]);
    vkCmdBindPipeline(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, scan.pipeline());
    context_.cmdPushDescriptorSet()(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, scan.layout(), 0, 3, writes);
    vkCmdPushConstants(commands_, scan.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof n, &n);
    vkCmdDispatch(commands_, groups[0], groups[1], groups[2]);
    readSinceBarrier_.insert(arg.buffer->handle());
    readSinceBarrier_.insert(snapshots[i]->handle());
  }
}

void Stream::dispatchFlat(const Kernel& kernel, std::span<const Arg> args, const void* push, uint32_t pushBytes,
                          uint64_t invocations) {
  const std::array<uint32_t, 3>& workgroup = kernel.key().workgroup;
  if (workgroup[1] != 1 || workgroup[2] != 1)
    throw Error("kernel '" + kernel.key().shader + "': dispatchFlat needs a workgroup of shape [x, 1, 1]");
  dispatch(kernel, args, push, pushBytes, flatGroups(invocations, workgroup[0]));
}

void Stream::copy(const Tensor& source, const Tensor& destination) {
  if (source.numel() != destination.numel())
    throw Error("copy from tensor " + toString(source.shape()) + " to " + toString(destination.shape()) +
                ": element counts differ");
  if (source.numel() == 0) return;
  begin();
  const bool inPlace = &source.buffer() == &destination.buffer();
  hold(source.buffer(), true, inPlace);
  if (!inPlace) hold(destination.buffer(), false, true);
  access(source.buffer(), true, false);
  access(destination.buffer(), false, true);
  VkBufferCopy region{0, 0, source.bytes()};
  vkCmdCopyBuffer(commands_, source.buffer().handle(), destination.buffer().handle(), 1, &region);
  readSinceBarrier_.insert(source.buffer().handle());
  writtenSinceBarrier_.insert(destination.buffer().handle());
}

namespace {

// Throws unless the parts fit `whole` at their offsets without overlapping, in ascending order.
void checkParts(const char* what, std::span<const Tensor> parts, std::span<const int64_t> offsets, const Tensor& whole) {
  if (parts.size() != offsets.size())
    throw Error(std::string(what) + ": " + std::to_string(parts.size()) + " parts but " +
                std::to_string(offsets.size()) + " offsets");
  int64_t end = 0;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (offsets[i] < end || offsets[i] + parts[i].numel() > whole.numel())
      throw Error(std::string(what) + ": part " + std::to_string(i) + " (" + toString(parts[i].shape()) +
                  " at element " + std::to_string(offsets[i]) + ") overlaps the part before it or ends past the " +
                  std::to_string(whole.numel()) + " elements of the whole");
    if (&parts[i].buffer() == &whole.buffer())
      throw Error(std::string(what) + ": part " + std::to_string(i) + " is the whole tensor itself");
    end = offsets[i] + parts[i].numel();
  }
}

VkBufferCopy region(int64_t sourceElement, int64_t destinationElement, int64_t elements) {
  constexpr auto kFloat = static_cast<VkDeviceSize>(sizeof(float));
  return {static_cast<VkDeviceSize>(sourceElement) * kFloat, static_cast<VkDeviceSize>(destinationElement) * kFloat,
          static_cast<VkDeviceSize>(elements) * kFloat};
}

}  // namespace

void Stream::gather(std::span<const Tensor> parts, std::span<const int64_t> offsets, const Tensor& whole) {
  checkParts("gather", parts, offsets, whole);
  if (parts.empty()) return;
  begin();
  // `whole` is held as read too: elements outside the parts keep their contents, so its memory may not
  // be swapped for a dead tensor's.
  hold(whole.buffer(), true, true);
  for (const Tensor& part : parts) hold(part.buffer(), true, false);
  for (const Tensor& part : parts) access(part.buffer(), true, false);
  access(whole.buffer(), false, true);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].numel() == 0) continue;
    const VkBufferCopy copyRegion = region(0, offsets[i], parts[i].numel());
    vkCmdCopyBuffer(commands_, parts[i].buffer().handle(), whole.buffer().handle(), 1, &copyRegion);
    readSinceBarrier_.insert(parts[i].buffer().handle());
  }
  writtenSinceBarrier_.insert(whole.buffer().handle());
}

void Stream::scatter(const Tensor& whole, std::span<const int64_t> offsets, std::span<const Tensor> parts) {
  checkParts("scatter", parts, offsets, whole);
  std::unordered_set<const Buffer*> distinct;
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (!distinct.insert(&parts[i].buffer()).second)
      throw Error("scatter: part " + std::to_string(i) + " shares its buffer with an earlier part");
  if (parts.empty()) return;
  begin();
  hold(whole.buffer(), true, false);
  for (const Tensor& part : parts) hold(part.buffer(), false, true);
  access(whole.buffer(), true, false);
  for (const Tensor& part : parts) access(part.buffer(), false, true);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].numel() == 0) continue;
    const VkBufferCopy copyRegion = region(offsets[i], 0, parts[i].numel());
    vkCmdCopyBuffer(commands_, whole.buffer().handle(), parts[i].buffer().handle(), 1, &copyRegion);
    writtenSinceBarrier_.insert(parts[i].buffer().handle());
  }
  readSinceBarrier_.insert(whole.buffer().handle());
}

void Stream::fillZero(const Tensor& tensor) {
  if (tensor.numel() == 0) return;
  begin();
  hold(tensor.buffer(), false, true);
  access(tensor.buffer(), false, true);
  vkCmdFillBuffer(commands_, tensor.buffer().handle(), 0, tensor.bytes(), 0);
  writtenSinceBarrier_.insert(tensor.buffer().handle());
}

Tensor Stream::derived(const Tensor& source, const std::string& key) const {
  const auto kept = derived_.find({&source.buffer(), key});
  if (kept == derived_.end()) return {};
  const auto writes = writesRecorded_.find(&source.buffer());
  const uint64_t now = writes == writesRecorded_.end() ? 0 : writes->second;
  return now == kept->second.writesBefore ? kept->second.tensor : Tensor{};
}

void Stream::keepDerived(const Tensor& source, const std::string& key, const Tensor& derived) {
  const auto writes = writesRecorded_.find(&source.buffer());
  derived_[{&source.buffer(), key}] =
      Derived{source.sharedBuffer(), writes == writesRecorded_.end() ? 0 : writes->second, derived};
}

void Stream::beginRegion(std::string name, std::string detail) {
  if (!queries_) return;
  begin();
  if (queriesUsed_ + 2 > 2 * options_.maxRegions)
    throw Error("command stream: more than " + std::to_string(options_.maxRegions) + " timed regions");
  regions_.push_back({std::move(name), std::move(detail), queriesUsed_, 0});
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
      times_.push_back({region.name, ticks * context_.info().timestampPeriodNs, region.detail});
    }
  }
  if (check_) check_->throwIfFound();
}

void Stream::reset() {
  if (recording_) vkCheck(vkResetCommandBuffer(commands_, 0), "resetting a command stream");
  recording_ = false;
  ended_ = false;
  dispatches_ = 0;
  barriers_ = 0;
  readSinceBarrier_.clear();
  writtenSinceBarrier_.clear();
  writesRecorded_.clear();
  derived_.clear();
  memory_.clear();
  if (check_) check_->clear();
  regions_.clear();
  openRegions_.clear();
  queriesUsed_ = 0;
  times_.clear();
}

}  // namespace smokesvd

#include "runtime/buffer.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <string>

#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd {
namespace {

constexpr VkBufferUsageFlags kUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                                      VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

std::string mebibytes(VkDeviceSize bytes) {
  return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB";
}

uint32_t chooseMemoryType(VkPhysicalDevice device, uint32_t allowed, VkMemoryPropertyFlags wanted) {
  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(device, &memory);
  for (uint32_t type = 0; type < memory.memoryTypeCount; ++type) {
    if ((allowed & (1u << type)) && (memory.memoryTypes[type].propertyFlags & wanted) == wanted) return type;
  }
  throw Error("no Vulkan memory type has the properties smokesvd needs (flags " + std::to_string(wanted) + ")");
}

}  // namespace

BufferMemory::BufferMemory(Context& context, VkDeviceSize bytes, bool hostVisible) : context_(context), capacity_(bytes) {
  VkDevice device = context.device();
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = bytes;
  info.usage = kUsage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  vkCheck(vkCreateBuffer(device, &info, nullptr, &buffer_), "creating a buffer of " + mebibytes(bytes));

  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device, buffer_, &requirements);
  const bool mappable = hostVisible || context.mappedBuffers();
  const VkMemoryPropertyFlags wanted = mappable
                                           ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                           : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex = chooseMemoryType(context.physicalDevice(), requirements.memoryTypeBits, wanted);
  VkResult result = vkAllocateMemory(device, &allocate, nullptr, &memory_);
  if (result != VK_SUCCESS) {
    vkDestroyBuffer(device, buffer_, nullptr);
    throw VulkanError(result, "allocating " + mebibytes(bytes) + " of device memory");
  }
  vkCheck(vkBindBufferMemory(device, buffer_, memory_, 0), "binding buffer memory");
  if (mappable) vkCheck(vkMapMemory(device, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "mapping buffer memory");
}

BufferMemory::~BufferMemory() {
  VkDevice device = context_.device();
  for (VkBufferView view : views_)
    if (view) vkDestroyBufferView(device, view, nullptr);
  vkDestroyBuffer(device, buffer_, nullptr);
  vkFreeMemory(device, memory_, nullptr);
}

VkBufferView BufferMemory::view(TexelFormat format) {
  VkBufferView& view = views_[static_cast<int>(format)];
  if (view) return view;
  const VkDeviceSize texelBytes = format == TexelFormat::Float ? 4 : 16;
  const VkDeviceSize maxBytes = VkDeviceSize{context_.info().maxTexelBufferElements} * texelBytes;
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer_;
  info.format = format == TexelFormat::Float ? VK_FORMAT_R32_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
  info.offset = 0;
  info.range = std::min(capacity_, maxBytes) / texelBytes * texelBytes;
  vkCheck(vkCreateBufferView(context_.device(), &info, nullptr, &view), "creating a texel-buffer view");
  return view;
}

void BufferMemory::write(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
    return;
  }
  BufferMemory staging(context_, bytes, true);
  std::memcpy(staging.mapped(), data, bytes);
  context_.runOnce("uploading " + mebibytes(bytes), [&](VkCommandBuffer commands) {
    VkBufferCopy region{0, offset, bytes};
    vkCmdCopyBuffer(commands, staging.handle(), buffer_, 1, &region);
  });
}

void BufferMemory::read(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
    return;
  }
  BufferMemory staging(context_, bytes, true);
  context_.runOnce("downloading " + mebibytes(bytes), [&](VkCommandBuffer commands) {
    VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(commands, buffer_, staging.handle(), 1, &region);
  });
  std::memcpy(data, staging.mapped(), bytes);
}

uint64_t nextSerial() {
  static std::atomic<uint64_t> serial{0};
  return ++serial;
}

Buffer::Buffer(Context& context, VkDeviceSize bytes, bool hostVisible)
    : memory_(std::make_shared<BufferMemory>(context, bytes, hostVisible)) {}

Buffer::Buffer(std::shared_ptr<BufferMemory> memory, uint64_t serial) : memory_(std::move(memory)), serial_(serial) {}

void Buffer::write(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  BufferMemory::Lives& lives = memory_->lives_;
  if (lives.reused)
    throw Error("writing " + std::to_string(bytes) + " bytes from the host into a buffer that a recorded stream "
                "also uses for earlier tensors (buffer reuse within the recording); the write would reach them "
                "when it runs. Upload before the stream first writes the tensor, or reset() the stream first");
  untouched_ = false;
  if (lives.recording != 0) lives.foreign = true;
  derived_.clear();
  memory_->write(data, bytes, offset);
}

const Buffer::Derived* Buffer::derived(const std::string& key) const {
  const auto kept = derived_.find(key);
  return kept == derived_.end() ? nullptr : &kept->second;
}

void Buffer::keepDerived(const std::string& key, Derived derived) {
  if (!constant_) throw Error("keeping a derived buffer with a buffer that is not constant");
  derived_[key] = std::move(derived);
}

void Buffer::read(void* data, VkDeviceSize bytes, VkDeviceSize offset) const { memory_->read(data, bytes, offset); }

BufferPool::~BufferPool() { trim(); }

VkDeviceSize BufferPool::sizeClass(VkDeviceSize bytes) {
  if (bytes <= 256) return 256;
  const VkDeviceSize power = std::bit_floor(bytes);
  if (bytes == power) return power;
  const VkDeviceSize threeHalves = power + power / 2;
  return bytes <= threeHalves ? threeHalves : power * 2;
}

std::shared_ptr<Buffer> BufferPool::acquire(VkDeviceSize bytes, std::string_view what) {
  const uint64_t limit = context_.info().maxTensorBytes();
  if (bytes > limit) {
    throw Error(std::string(what) + " needs " + mebibytes(bytes) + ", more than the " + mebibytes(limit) +
                " one tensor may span on '" + context_.info().name +
                "' (its storage-buffer range and texel-buffer size)");
  }
  const VkDeviceSize capacity = sizeClass(bytes);
  std::unique_ptr<BufferMemory> memory;
  {
    std::lock_guard lock(mutex_);
    auto found = idle_.find(capacity);
    if (found != idle_.end()) {
      memory = std::move(found->second);
      idle_.erase(found);
      stats_.idleBytes -= capacity;
      ++stats_.reused;
    }
  }
  if (!memory) {
    try {
      memory = std::make_unique<BufferMemory>(context_, capacity, false);
    } catch (const VulkanError& error) {
      if (error.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY) throw;
      trim();  // idle buffers of other classes may be what stands in the way
      memory = std::make_unique<BufferMemory>(context_, capacity, false);
    }
    std::lock_guard lock(mutex_);
    ++stats_.created;
    stats_.allocatedBytes += capacity;
    stats_.peakAllocatedBytes = std::max(stats_.peakAllocatedBytes, stats_.allocatedBytes);
  }
  {
    std::lock_guard lock(mutex_);
    stats_.liveBytes += capacity;
    stats_.peakLiveBytes = std::max(stats_.peakLiveBytes, stats_.liveBytes);
  }
  std::shared_ptr<BufferMemory> shared(memory.release(), [this](BufferMemory* released) { giveBack(released); });
  return std::make_shared<Buffer>(std::move(shared), nextSerial());
}

void BufferPool::giveBack(BufferMemory* memory) {
  std::lock_guard lock(mutex_);
  stats_.idleBytes += memory->capacity();
  stats_.liveBytes -= memory->capacity();
  idle_.emplace(memory->capacity(), std::unique_ptr<BufferMemory>(memory));
}

void BufferPool::trim() {
  std::multimap<VkDeviceSize, std::unique_ptr<BufferMemory>> released;
  std::lock_guard lock(mutex_);
  released.swap(idle_);
  stats_.allocatedBytes -= stats_.idleBytes;
  stats_.idleBytes = 0;
}

BufferPool::Stats BufferPool::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void BufferPool::resetPeaks() {
  std::lock_guard lock(mutex_);
  stats_.peakLiveBytes = stats_.liveBytes;
  stats_.peakAllocatedBytes = stats_.allocatedBytes;
}

}  // namespace smokesvd

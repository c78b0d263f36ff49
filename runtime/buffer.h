// Device buffers (RAII) and the pool that recycles them so steady-state work allocates nothing new.
//
// Every buffer can be bound as a storage buffer (read/write) and read through a uniform texel buffer
// view (`samplerBuffer` + texelFetch), which is the fast read path on lavapipe. Where memory is unified
// (CPU or integrated device) buffers live in host-visible memory and are read and written by memcpy;
// on a discrete GPU they are device-local and go through a staging buffer.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <string_view>

#include <vulkan/vulkan.h>

namespace smokesvd {

class Context;

// How a texel-buffer view presents the bytes: one float per texel, or four (vec4 fetches).
enum class TexelFormat { Float, Float4 };

class Buffer {
 public:
  // `hostVisible` forces host-visible memory (staging); otherwise the device decides.
  Buffer(Context& context, VkDeviceSize bytes, bool hostVisible = false);
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize capacity() const { return capacity_; }
  void* mapped() const { return mapped_; }
  // A view over the whole buffer (created on first use, kept with the buffer).
  VkBufferView view(TexelFormat format);

  void write(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  void read(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;

 private:
  Context& context_;
  VkDeviceSize capacity_ = 0;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  VkBufferView views_[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
};

// Hands out buffers rounded up to a size class (2^k or 1.5*2^k bytes, at least 256) and takes them
// back when their last owner lets go, keeping them for the next request of the same class.
class BufferPool {
 public:
  struct Stats {
    std::size_t created = 0;      // buffers allocated from the driver
    std::size_t reused = 0;       // requests served from idle buffers
    VkDeviceSize idleBytes = 0;   // held by the pool, unused
  };

  explicit BufferPool(Context& context) : context_(context) {}
  ~BufferPool();

  // `what` names the request in errors, e.g. "tensor [1, 32, 64, 64]".
  std::shared_ptr<Buffer> acquire(VkDeviceSize bytes, std::string_view what);
  void trim();  // frees every idle buffer
  Stats stats() const;

  static VkDeviceSize sizeClass(VkDeviceSize bytes);

 private:
  void giveBack(Buffer* buffer);

  Context& context_;
  mutable std::mutex mutex_;
  std::multimap<VkDeviceSize, std::unique_ptr<Buffer>> idle_;
  Stats stats_;
};

}  // namespace smokesvd

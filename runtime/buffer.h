// Device buffers (RAII) and the pool that recycles them so steady-state work allocates nothing new.
//
// A BufferMemory is one allocation: a VkBuffer, its memory and its texel views. Tensors share a Buffer,
// which is backed by one BufferMemory; a recording stream may back a new Buffer with the memory of one
// whose tensors are all gone (runtime/recording_memory.h), so the memory is shared out separately.
//
// Every buffer can be bound as a storage buffer (read/write) and read through a uniform texel buffer
// view (`samplerBuffer` + texelFetch), which is the fast read path on lavapipe. Where memory is unified
// (CPU or integrated device) buffers live in host-visible memory and are read and written by memcpy;
// on a discrete GPU they are device-local and go through a staging buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

namespace smokesvd {

class Context;
class RecordingMemory;

// How a texel-buffer view presents the bytes: one float per texel, or four (vec4 fetches).
enum class TexelFormat { Float, Float4 };

class BufferMemory {
 public:
  // `hostVisible` forces host-visible memory (staging); otherwise the device decides.
  BufferMemory(Context& context, VkDeviceSize bytes, bool hostVisible);
  ~BufferMemory();
  BufferMemory(const BufferMemory&) = delete;
  BufferMemory& operator=(const BufferMemory&) = delete;

  Context& context() const { return context_; }
  VkBuffer handle() const { return buffer_; }
  VkDeviceSize capacity() const { return capacity_; }
  void* mapped() const { return mapped_; }
  // A view over the whole buffer (created on first use, kept with the buffer).
  VkBufferView view(TexelFormat format);

  void write(const void* data, VkDeviceSize bytes, VkDeviceSize offset);
  void read(void* data, VkDeviceSize bytes, VkDeviceSize offset) const;

 private:
  friend class Buffer;
  friend class RecordingMemory;
  // What the recording that owns this memory's lifetime knows of it (RecordingMemory).
  struct Lives {
    uint64_t recording = 0;  // the recording it was born in, 0 if none
    bool foreign = false;    // written by the host or used by another stream since: never reused
    bool reused = false;     // it backs more than one tensor of that recording
  };

  Context& context_;
  VkDeviceSize capacity_ = 0;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  VkBufferView views_[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
  Lives lives_;
};

// What a Tensor points to. Copies of a tensor, and its reshaped views, share one Buffer.
class Buffer {
 public:
  // A buffer with memory of its own (staging, small stream-private buffers).
  Buffer(Context& context, VkDeviceSize bytes, bool hostVisible = false);
  // A buffer over pooled memory; `serial` orders it against recordings (RecordingMemory).
  Buffer(std::shared_ptr<BufferMemory> memory, uint64_t serial);
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return memory_->handle(); }
  VkDeviceSize capacity() const { return memory_->capacity(); }
  void* mapped() const { return memory_->mapped(); }
  VkBufferView view(TexelFormat format) { return memory_->view(format); }

  // Throws Error if a recording that is still held reuses this memory for earlier tensors: the write
  // would reach them too when the recording runs. Drops what was derived from a constant buffer.
  void write(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  void read(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;

  // A constant buffer (frozen weights) is written by the host only, never by a stream (Stream throws). What
  // recorded commands derive from it (a convolution's packed weights) can then be kept with it, under a key,
  // for every later recording: derived() until the host writes it again.
  struct Derived {
    std::vector<int64_t> shape;
    std::shared_ptr<Buffer> buffer;
  };
  void markConstant() { constant_ = true; }
  bool constant() const { return constant_; }
  const Derived* derived(const std::string& key) const;
  void keepDerived(const std::string& key, Derived derived);

 private:
  friend class RecordingMemory;
  std::shared_ptr<BufferMemory> memory_;
  uint64_t serial_ = 0;  // from nextSerial() when created; 0 for buffers outside the pool
  bool untouched_ = true;  // neither written by the host nor used by a stream yet
  bool constant_ = false;
  std::map<std::string, Derived> derived_;  // constant buffers only
};

// A process-wide increasing number: buffers and recordings take one when they begin.
uint64_t nextSerial();

// Hands out buffers rounded up to a size class (2^k or 1.5*2^k bytes, at least 256) and takes them
// back when their last owner lets go, keeping them for the next request of the same class.
class BufferPool {
 public:
  struct Stats {
    std::size_t created = 0;             // buffers allocated from the driver
    std::size_t reused = 0;              // requests served from idle buffers
    VkDeviceSize idleBytes = 0;          // held by the pool, unused
    VkDeviceSize liveBytes = 0;          // handed out: held by tensors or recordings
    VkDeviceSize allocatedBytes = 0;     // device memory the pool has from the driver (live + idle)
    VkDeviceSize peakLiveBytes = 0;      // high-water marks since creation or resetPeaks()
    VkDeviceSize peakAllocatedBytes = 0;
  };

  explicit BufferPool(Context& context) : context_(context) {}
  ~BufferPool();

  // `what` names the request in errors, e.g. "tensor [1, 32, 64, 64]".
  std::shared_ptr<Buffer> acquire(VkDeviceSize bytes, std::string_view what);
  void trim();  // frees every idle buffer
  Stats stats() const;
  void resetPeaks();  // the high-water marks restart from the current figures

  static VkDeviceSize sizeClass(VkDeviceSize bytes);

 private:
  void giveBack(BufferMemory* memory);

  Context& context_;
  mutable std::mutex mutex_;
  std::multimap<VkDeviceSize, std::unique_ptr<BufferMemory>> idle_;
  Stats stats_;
};

}  // namespace smokesvd

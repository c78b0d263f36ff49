// A command stream: many dispatches recorded into one command buffer, submitted together.
//
// The stream knows from each kernel's reflected bindings which buffers a dispatch reads and writes,
// and inserts a memory barrier exactly where a dispatch would otherwise read a buffer written before it
// (RAW) or write one read or written before it (WAR, WAW). Callers never write barriers.
//
// It holds the memory of every buffer its commands use until reset(), and backs tensors it creates later
// with the memory of tensors that are gone (runtime/recording_memory.h). With SMOKESVD_CHECK=1 it scans
// every buffer a dispatch writes for NaN and Inf (runtime/finite_check.h).
//
// Typical use:
//   Stream stream(context);
//   stream.dispatchFlat(kernel, {x, y}, Push{n}, n);
//   stream.submit();   // waits; submit() again re-runs the same recording, reset() starts a new one
#pragma once

#include <array>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <vulkan/vulkan.h>

#include "runtime/buffer.h"
#include "runtime/kernel.h"
#include "runtime/recording_memory.h"
#include "runtime/tensor.h"

namespace smokesvd {

class Context;
class FiniteCheck;

// One argument of a dispatch, bound to the next binding number. Texel-buffer bindings read through a
// float view unless the argument asks for vec4 texels (asVec4).
struct Arg {
  Arg(const Tensor& tensor)  // NOLINT: implicit on purpose
      : buffer(tensor.sharedBuffer()), bytes(tensor.boundBytes()), shape(&tensor.shape()) {}
  Arg(std::shared_ptr<Buffer> buffer_, uint64_t bytes_, TexelFormat format_ = TexelFormat::Float)
      : buffer(std::move(buffer_)), bytes(bytes_), format(format_) {}
  std::shared_ptr<Buffer> buffer;
  uint64_t bytes = 0;
  TexelFormat format = TexelFormat::Float;
  const Shape* shape = nullptr;  // the tensor's, for the element index of a finite-check report
};

inline Arg asVec4(const Tensor& tensor) {
  Arg arg(tensor);
  arg.format = TexelFormat::Float4;
  return arg;
}

struct StreamOptions {
  // Time every dispatch as a region named after its shader, its detail the dispatch's workgroup grid,
  // specialisation constants and push constants (RegionTime::detail).
  bool profileDispatches = false;
  uint32_t maxRegions = 4096;      // timestamp regions one recording can hold
  // Back tensors created during the recording with the memory of its tensors that are gone
  // (runtime/recording_memory.h). Off: every tensor the recording uses keeps its own memory.
  bool reuseBuffers = true;
  // Scan every buffer a dispatch writes for NaN/Inf; submit() throws at the first (runtime/finite_check.h).
  // Also on for every stream when the context has ContextOptions::checkFinite (SMOKESVD_CHECK=1, --check).
  bool checkFinite = false;
};

struct RegionTime {
  std::string name;
  double nanoseconds = 0;
  // A profiled dispatch's "groups 3x112x1; constants 3,3,3,1; push 16,70992": its workgroup grid, the
  // kernel's specialisation constants from constant_id 3 on, and its push constants as 32-bit integers in
  // their order (a float field shows its bits); empty for a region of beginRegion().
  std::string detail;
};

class Stream {
 public:
  explicit Stream(Context& context, StreamOptions options = {});
  ~Stream();
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;

  Context& context() const { return context_; }
  // The cached kernel for a shader, workgroup size and specialization constants (ids 3, 4, ...).
  const Kernel& kernel(const std::string& shader, std::array<uint32_t, 3> workgroup = {64, 1, 1},
                       std::vector<int32_t> constants = {}) const;

  // Records `groups` workgroups of `kernel` with `args` bound to bindings 0..n-1 and `push` as push constants.
  void dispatch(const Kernel& kernel, std::span<const Arg> args, const void* push, uint32_t pushBytes,
                std::array<uint32_t, 3> groups);
  template <typename Push>
  void dispatch(const Kernel& kernel, std::initializer_list<Arg> args, const Push& push,
                std::array<uint32_t, 3> groups) {
    dispatch(kernel, std::span<const Arg>(args.begin(), args.size()), &push, sizeof(Push), groups);
  }
  // One invocation per item, `invocations` in all, laid out on a 2D grid of workgroups; shaders recover
  // the item index with flat_index() from shaders/common/index.glsl and return when it is >= the count.
  void dispatchFlat(const Kernel& kernel, std::span<const Arg> args, const void* push, uint32_t pushBytes,
                    uint64_t invocations);
  template <typename Push>
  void dispatchFlat(const Kernel& kernel, std::initializer_list<Arg> args, const Push& push, uint64_t invocations) {
    dispatchFlat(kernel, std::span<const Arg>(args.begin(), args.size()), &push, sizeof(Push), invocations);
  }

  void copy(const Tensor& source, const Tensor& destination);  // same number of elements
  void fillZero(const Tensor& tensor);
  // Copies each part into `whole` from element offsets[i] on (gather), or out of it (scatter): one transfer
  // command per part and no barrier between them, since the parts' ranges of `whole` may not overlap
  // (offsets ascending, each part ending before the next begins). On lavapipe a transfer command costs
  // about a microsecond where a dispatch costs tens to a hundred (docs/benchmarks.md, dispatch/), so
  // kernels that do the same to many small tensors gather them into one and run once (nets/optim/).
  // Elements of `whole` outside the parts are left as they are.
  void gather(std::span<const Tensor> parts, std::span<const int64_t> offsets, const Tensor& whole);
  void scatter(const Tensor& whole, std::span<const int64_t> offsets, std::span<const Tensor> parts);

  // Tensors derived from another by recorded commands (a convolution's packed weights), kept for the later
  // commands of the same recording: derived(source, key) is the tensor kept under `key` for `source` if no
  // command recorded since has written `source`, else undefined. Kept tensors (and their sources) stay
  // alive until reset(). The same frozen network run several times in one recording packs its weights once.
  Tensor derived(const Tensor& source, const std::string& key) const;
  void keepDerived(const Tensor& source, const std::string& key, const Tensor& derived);

  // Named GPU-timed regions; they may nest. Times are available after submit().
  void beginRegion(std::string name, std::string detail = {});
  void endRegion();

  // Ends recording (first time), submits, waits. May be called again to run the same recording.
  void submit();
  // Drops the recording (and the buffers it kept alive) so a new one can start.
  void reset();

  std::vector<RegionTime> regionTimes() const { return times_; }
  uint32_t dispatchCount() const { return dispatches_; }
  uint32_t barrierCount() const { return barriers_; }
  // The memory the recording holds (all of it stays alive until reset()) and what reuse saved.
  StreamMemory memory() const { return memory_.stats(); }
  bool checksFinite() const { return check_ != nullptr; }

 private:
  void release();
  void begin();
  // Holds the memory of each buffer the dispatch binds (which may re-back a fresh output, so before any
  // barrier decision or descriptor is made).
  void useBuffers(std::span<const Arg> args, const std::vector<BindingInfo>& bindings);
  // Holds `buffer`'s memory for the recording (RecordingMemory::use).
  void hold(Buffer& buffer, bool reads, bool writes);
  // Emits a barrier if this access would race with one recorded since the last barrier.
  void access(const Buffer& buffer, bool reads, bool writes);
  void barrier();
  // The finite check: copies of the float buffers a dispatch is about to write (null for the other
  // arguments), then the scans of what it wrote.
  std::vector<Buffer*> snapshotWrites(std::span<const Arg> args, const std::vector<BindingInfo>& bindings);
  void scanWrites(const std::string& shader, std::span<const Arg> args, const std::vector<BindingInfo>& bindings,
                  const std::vector<Buffer*>& snapshots);

  Context& context_;
  StreamOptions options_;
  VkCommandBuffer commands_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  bool recording_ = false;
  bool ended_ = false;
  uint32_t dispatches_ = 0;
  uint32_t barriers_ = 0;
  std::unordered_set<VkBuffer> readSinceBarrier_;
  std::unordered_set<VkBuffer> writtenSinceBarrier_;
  std::unordered_map<const Buffer*, uint64_t> writesRecorded_;  // per buffer, for derived tensors
  struct Derived {
    std::shared_ptr<Buffer> source;  // held, so that no other buffer takes its address
    uint64_t writesBefore = 0;       // writesRecorded_ of the source when it was kept
    Tensor tensor;
  };
  std::map<std::pair<const Buffer*, std::string>, Derived> derived_;
  RecordingMemory memory_;
  std::unique_ptr<FiniteCheck> check_;
  struct Region {
    std::string name, detail;
    uint32_t beginQuery = 0;
    uint32_t endQuery = 0;
  };
  std::vector<Region> regions_;
  std::vector<std::size_t> openRegions_;
  uint32_t queriesUsed_ = 0;
  std::vector<RegionTime> times_;
};

}  // namespace smokesvd

// The NaN/Inf guard (SMOKESVD_CHECK=1, `smokesvd --check`, StreamOptions::checkFinite): a debugging mode.
//
// Around every dispatch the stream records, for each float buffer the dispatch writes (every storage
// buffer the kernel does not declare readonly, except blocks of `int`s and blocks named *NonFinite, see
// BindingInfo::finiteFloats), a copy of the buffer before the dispatch and a scan after it
// (shaders/runtime/check_finite.comp). The scan looks only at elements the dispatch changed, so kernels
// that write part of a buffer are judged by what they wrote. Each scan keeps the smallest index of a
// non-finite element in a report slot of its own, on the device, so nothing is downloaded but the
// slots, and the recording itself resets its slots: a re-submitted recording is checked at every run.
// submit() reads the slots in recording order and throws at the first scan that found one, naming the
// dispatch, its shader, the binding and the element (its flat index and, where the tensor's shape is
// known, its index in that shape).
//
// The whole recording has still run by then; what it wrote after the first non-finite value is not
// meaningful. A NaN written over the very same NaN bits goes unseen (it was there before). Off by
// default: a stream without the check records nothing extra.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "runtime/buffer.h"
#include "runtime/spirv_reflect.h"
#include "runtime/tensor.h"

namespace smokesvd {

class Context;

class FiniteCheck {
 public:
  // Where one scan reports: a range of a host-visible report buffer. A chunk's first slot comes with
  // `resetChunk`: the recording must fill that buffer with 0xFFFFFFFF (and a barrier) before the scan.
  struct Slot {
    VkBuffer report = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
    VkDeviceSize range = 0;
    bool resetChunk = false;
  };
  static constexpr const char* kShader = "runtime/check_finite";

  explicit FiniteCheck(Context& context) : context_(context) {}

  // Registers the scan of `binding` of dispatch number `dispatch` (from 1), `elements` floats of a tensor
  // of shape `shape` (empty if unknown).
  Slot add(const std::string& shader, uint32_t dispatch, const BindingInfo& binding, uint64_t elements, Shape shape);
  // A buffer of at least `bytes` for the copy of the `index`-th scanned binding of a dispatch (the stream
  // orders its uses with barriers like any other buffer's).
  Buffer& snapshot(std::size_t index, uint64_t bytes);
  // After a submission: throws Error describing the first non-finite value the scans found.
  void throwIfFound() const;
  void clear();

 private:
  struct Scan {
    std::string shader;
    uint32_t dispatch = 0;
    uint32_t binding = 0;
    std::string bindingName;
    uint64_t elements = 0;
    Shape shape;
  };
  static constexpr VkDeviceSize kSlotBytes = 256;  // the largest minStorageBufferOffsetAlignment Vulkan allows
  static constexpr uint32_t kSlotsPerChunk = 1024;

  Context& context_;
  std::vector<std::unique_ptr<Buffer>> chunks_;
  std::vector<Scan> scans_;
  std::vector<std::unique_ptr<Buffer>> snapshots_;  // all stay alive: the recording's commands use them
  std::vector<Buffer*> snapshotFor_;                // the current one for each binding position
};

}  // namespace smokesvd

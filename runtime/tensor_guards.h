// Poisoned, guarded tensors: a test mode (ContextOptions::guardTensors) in which a kernel that forgets
// to write an element, or writes past the end of a tensor, is seen.
//
// In a guarded context every tensor buffer is laid out as
//   [ elements (NaN) | up to 12 bytes of vec4 padding | kGuardBytes of guard words ]
// The elements start as NaN, so an element no kernel wrote reads NaN. The padding is the tail a vec4
// store may fill (docs/runtime.md: tensors are padded to 16 bytes). Storage bindings of the tensor span
// the guard too (Tensor::boundBytes), so a store past the padding lands in it instead of being dropped
// by a robust device; check() reports every guard word that no longer holds kGuardWord.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace smokesvd {

class Buffer;
class Tensor;

class TensorGuards {
 public:
  static constexpr uint64_t kGuardBytes = 256;
  static constexpr uint32_t kGuardWord = 0x7FBADBADu;  // a NaN no kernel computes

  // The elements rounded up to whole vec4s: where the guard begins.
  static uint64_t guardOffset(uint64_t elementBytes) { return (elementBytes + 15) / 16 * 16; }
  // Bytes a guarded tensor of `elementBytes` occupies and its storage bindings span.
  static uint64_t guardedBytes(uint64_t elementBytes) { return guardOffset(elementBytes) + kGuardBytes; }

  // Fills a new tensor's elements and padding with NaN and its guard with kGuardWord, and remembers it.
  void arm(const Tensor& tensor);
  // One line per remembered tensor, still alive, whose guard was written ("tensor [2, 3]: 4 guard words
  // written past its end, the first 0 floats after the padding, with 1.5"); empty when none was.
  std::vector<std::string> violations();
  // Forgets every tensor armed so far (the next violations() looks only at later ones).
  void clear();

 private:
  struct Armed {
    std::weak_ptr<Buffer> buffer;
    uint64_t guardOffset = 0;
    std::string what;
  };
  std::mutex mutex_;
  std::vector<Armed> armed_;
};

}  // namespace smokesvd

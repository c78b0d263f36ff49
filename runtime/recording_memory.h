// The memory a recording stream holds, and its reuse within the recording (as ggml-alloc plans by liveness).
//
// Recorded commands run later, and again at every re-submission, so every memory a recording's commands
// use stays alive until the stream is reset. Within one recording, though, a tensor that is gone on the
// host (no Tensor refers to its buffer) after its last use has been recorded, holds memory nothing will
// read again: a tensor created later in the same recording can be backed by it. The stream then inserts
// the write-after-read barrier on that memory like on any other (barriers are tracked per VkBuffer), and
// every submission replays the same reuse in the same order.
//
// Reuse must not change what any submission computes, so it is limited to what the recording alone
// decides:
//  - the memory was *born* in this recording: first used by it, from a buffer created after the
//    recording began that nothing had written yet; it has not been written by the host or used by any
//    other stream since (those could hold contents the recording reads at its start);
//  - it goes to a buffer created after the recording began, at that buffer's first use, and only if that
//    use writes it without reading it (a tensor whose contents come from the host or another stream
//    keeps memory of its own).
// A memory that backs several tensors may then be read by anyone, but written only by this recording:
// Buffer::write from the host, and a write recorded by another stream, are errors until reset().
//
// Forward activations die when the tape's backward has used them (Tape::backward drops each op's closure
// once it has run); gradients die once their consumer is recorded.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "runtime/buffer.h"

namespace smokesvd {

struct StreamMemory {
  uint64_t heldBytes = 0;     // distinct memories the recording holds: its footprint while it is held
  uint32_t heldBuffers = 0;
  uint64_t reusedBytes = 0;   // given to later tensors from memory the recording already held
  uint32_t reusedBuffers = 0;
  uint64_t bytesWithoutReuse() const { return heldBytes + reusedBytes; }
};

class RecordingMemory {
 public:
  explicit RecordingMemory(bool reuse);
  ~RecordingMemory();
  RecordingMemory(const RecordingMemory&) = delete;
  RecordingMemory& operator=(const RecordingMemory&) = delete;

  // Before a command that uses `buffer` is recorded: holds its memory for the recording and, where the
  // rules above allow it, first backs `buffer` with the memory of a dead tensor of the recording.
  // `recent(handle)` tells whether the stream has recorded an access to a memory since its last
  // barrier: such memory is taken only if no other is dead, since reusing it costs a barrier.
  // Throws Error if the command would write memory another recording reuses.
  void use(Buffer& buffer, bool reads, bool writes, const std::function<bool(VkBuffer)>& recent);
  // Lets go of everything; what is recorded next is a new recording.
  void clear();
  StreamMemory stats() const { return stats_; }

 private:
  void hold(const std::shared_ptr<BufferMemory>& memory, bool born);
  std::shared_ptr<BufferMemory> takeDead(VkDeviceSize capacity, const std::function<bool(VkBuffer)>& recent);

  bool reuse_;
  uint64_t recording_;
  std::vector<std::shared_ptr<BufferMemory>> held_;
  std::unordered_set<const BufferMemory*> heldSet_;
  std::unordered_map<VkDeviceSize, std::vector<std::size_t>> born_;  // indices into held_, by capacity
  StreamMemory stats_;
};

}  // namespace smokesvd

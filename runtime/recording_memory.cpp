#include "runtime/recording_memory.h"

#include "runtime/error.h"

namespace smokesvd {

RecordingMemory::RecordingMemory(bool reuse) : reuse_(reuse), recording_(nextSerial()) {}

RecordingMemory::~RecordingMemory() { clear(); }

void RecordingMemory::use(Buffer& buffer, bool reads, bool writes, const std::function<bool(VkBuffer)>& recent) {
  const bool untouched = buffer.untouched_;
  buffer.untouched_ = false;
  if (untouched && reuse_ && buffer.serial_ > recording_ && writes && !reads) {
    if (std::shared_ptr<BufferMemory> dead = takeDead(buffer.capacity(), recent)) {
      dead->lives_.reused = true;
      stats_.reusedBytes += dead->capacity();
      ++stats_.reusedBuffers;
      buffer.memory_ = std::move(dead);  // the buffer's own memory goes back to the pool
      return;
    }
  }
  BufferMemory::Lives& lives = buffer.memory_->lives_;
  if (untouched) {
    lives = {recording_, false, false};
    hold(buffer.memory_, true);
    return;
  }
  if (lives.recording != 0 && lives.recording != recording_) {
    if (writes && lives.reused)
      throw Error("a stream records a write to a buffer of " + std::to_string(buffer.capacity()) +
                  " bytes that another recorded stream reuses for several of its tensors (buffer reuse within "
                  "that recording); the write would reach them when that stream runs again. reset() the other "
                  "stream first, or give this tensor a buffer of its own (create it before that recording began)");
    lives.foreign = true;
  }
  hold(buffer.memory_, false);
}

void RecordingMemory::hold(const std::shared_ptr<BufferMemory>& memory, bool born) {
  if (!heldSet_.insert(memory.get()).second) return;
  if (born) born_[memory->capacity()].push_back(held_.size());
  held_.push_back(memory);
  stats_.heldBytes += memory->capacity();
  ++stats_.heldBuffers;
}

// The oldest memory born here that only the recording still holds and that no access since the last
// barrier uses; else the oldest that one does.
std::shared_ptr<BufferMemory> RecordingMemory::takeDead(VkDeviceSize capacity,
                                                        const std::function<bool(VkBuffer)>& recent) {
  auto found = born_.find(capacity);
  if (found == born_.end()) return nullptr;
  std::shared_ptr<BufferMemory> costsABarrier;
  for (std::size_t index : found->second) {
    const std::shared_ptr<BufferMemory>& memory = held_[index];
    if (memory.use_count() != 1 || memory->lives_.foreign) continue;
    if (!recent(memory->handle())) return memory;
    if (!costsABarrier) costsABarrier = memory;
  }
  return costsABarrier;
}

void RecordingMemory::clear() {
  for (const std::shared_ptr<BufferMemory>& memory : held_)
    if (memory->lives_.recording == recording_) memory->lives_ = {};
  held_.clear();
  heldSet_.clear();
  born_.clear();
  stats_ = {};
  recording_ = nextSerial();
}

}  // namespace smokesvd

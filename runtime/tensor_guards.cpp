#include "runtime/tensor_guards.h"

#include <bit>
#include <cstring>
#include <limits>

#include "runtime/buffer.h"
#include "runtime/tensor.h"

namespace smokesvd {
namespace {

constexpr std::size_t kGuardWords = TensorGuards::kGuardBytes / sizeof(uint32_t);

}  // namespace

void TensorGuards::arm(const Tensor& tensor) {
  const uint64_t offset = guardOffset(tensor.bytes());
  std::vector<uint32_t> words(offset / sizeof(uint32_t) + kGuardWords,
                              std::bit_cast<uint32_t>(std::numeric_limits<float>::quiet_NaN()));
  std::fill(words.begin() + static_cast<std::ptrdiff_t>(offset / sizeof(uint32_t)), words.end(), kGuardWord);
  tensor.buffer().write(words.data(), words.size() * sizeof(uint32_t));
  std::lock_guard lock(mutex_);
  std::erase_if(armed_, [](const Armed& armed) { return armed.buffer.expired(); });
  armed_.push_back({tensor.sharedBuffer(), offset, "tensor " + toString(tensor.shape())});
}

std::vector<std::string> TensorGuards::violations() {
  std::lock_guard lock(mutex_);
  std::vector<std::string> found;
  for (const Armed& armed : armed_) {
    const std::shared_ptr<Buffer> buffer = armed.buffer.lock();
    if (!buffer) continue;
    std::vector<uint32_t> words(kGuardWords);
    buffer->read(words.data(), kGuardBytes, armed.guardOffset);
    std::size_t written = 0, first = 0;
    for (std::size_t i = words.size(); i-- > 0;) {
      if (words[i] == kGuardWord) continue;
      ++written;
      first = i;
    }
    if (written == 0) continue;
    found.push_back(armed.what + ": " + std::to_string(written) + " guard words written past its end, the first " +
                    std::to_string(first) + " floats after its vec4 padding, with " +
                    std::to_string(std::bit_cast<float>(words[first])));
  }
  return found;
}

void TensorGuards::clear() {
  std::lock_guard lock(mutex_);
  armed_.clear();
}

}  // namespace smokesvd

#include "nets/diffusion/gaussian.h"

#include <cmath>
#include <numbers>

namespace smokesvd::diffusion {

uint64_t Gaussian::nextBits() {
  uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

double Gaussian::uniform() { return static_cast<double>(nextBits() >> 11) * 0x1.0p-53; }

double Gaussian::next() {
  if (hasSpare_) {
    hasSpare_ = false;
    return spare_;
  }
  const double u1 = 1.0 - uniform();  // (0, 1]: log is finite
  const double u2 = uniform();
  const double radius = std::sqrt(-2.0 * std::log(u1));
  spare_ = radius * std::sin(2.0 * std::numbers::pi * u2);
  hasSpare_ = true;
  return radius * std::cos(2.0 * std::numbers::pi * u2);
}

std::vector<float> Gaussian::values(std::size_t count) {
  std::vector<float> out(count);
  for (float& value : out) value = static_cast<float>(next());
  return out;
}

}  // namespace smokesvd::diffusion

// Seeded standard-normal numbers on the host, the same for a seed on every platform that rounds
// log, sqrt and cos alike: splitmix64 uniforms (53-bit) through the Box-Muller transform. The noise of
// diffusion training and sampling comes from here and is uploaded, so runs are reproducible.
#pragma once

#include <cstdint>
#include <vector>

namespace smokesvd::diffusion {

class Gaussian {
 public:
  explicit Gaussian(uint64_t seed) : state_(seed) {}
  double next();                                 // one N(0, 1) value
  std::vector<float> values(std::size_t count);  // count N(0, 1) values
  double uniform();                              // U[0, 1), from the same stream

 private:
  uint64_t nextBits();
  uint64_t state_;
  bool hasSpare_ = false;
  double spare_ = 0;
};

}  // namespace smokesvd::diffusion

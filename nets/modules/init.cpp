#include "nets/modules/init.h"

#include <cmath>

namespace smokesvd::modules {
namespace {

uint64_t fnv1a(const std::string& text) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (const char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

// splitmix64: a 64-bit state advanced by a constant, mixed into each output.
class SplitMix {
 public:
  explicit SplitMix(uint64_t state) : state_(state) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform01() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)

 private:
  uint64_t state_;
};

}  // namespace

Init Init::weight(WeightInit scheme, int64_t fanIn) {
  if (scheme == WeightInit::Zero) return constant(0.0);
  const auto fan = static_cast<double>(fanIn);
  if (scheme == WeightInit::Lecun) return uniform(std::sqrt(3.0 / fan));
  return uniform(scheme == WeightInit::He ? std::sqrt(6.0 / fan) : 1.0 / std::sqrt(fan));
}

Init Init::bias(WeightInit scheme, int64_t fanIn) {
  return scheme != WeightInit::TorchDefault ? constant(0.0) : uniform(1.0 / std::sqrt(static_cast<double>(fanIn)));
}

std::vector<float> drawValues(const Init& init, std::size_t count, uint64_t seed, const std::string& name) {
  std::vector<float> values(count, static_cast<float>(init.value));
  if (init.kind == Init::Kind::Constant) return values;
  SplitMix generator(SplitMix(seed).next() ^ fnv1a(name));
  for (float& value : values) value = static_cast<float>(init.bound * (2.0 * generator.uniform01() - 1.0));
  return values;
}

}  // namespace smokesvd::modules

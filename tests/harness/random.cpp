#include "tests/harness/random.h"

#include <limits>
#include <random>

namespace smokesvd::testing {

std::vector<float> randomValues(std::size_t n, uint64_t seed, float low, float high) {
  std::mt19937_64 generator(seed);
  std::uniform_real_distribution<float> distribution(low, high);
  std::vector<float> values(n);
  for (float& value : values) value = distribution(generator);
  return values;
}

Tensor randomTensor(Context& context, const Shape& shape, uint64_t seed, float low, float high,
                    std::vector<float>* values) {
  std::vector<float> host = randomValues(static_cast<std::size_t>(numElements(shape)), seed, low, high);
  Tensor tensor = Tensor::fromHost(context, shape, host);
  if (values) *values = std::move(host);
  return tensor;
}

Tensor poisonedTensor(Context& context, const Shape& shape) {
  std::vector<float> nan(static_cast<std::size_t>(numElements(shape)), std::numeric_limits<float>::quiet_NaN());
  return Tensor::fromHost(context, shape, nan);
}

}  // namespace smokesvd::testing

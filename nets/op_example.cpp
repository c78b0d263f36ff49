#include "nets/op_example.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace smokesvd::draw {
namespace {

std::size_t count(const Shape& shape) { return static_cast<std::size_t>(numElements(shape)); }

}  // namespace

InputDraw uniform(Shape shape, float low, float high) {
  return {std::move(shape), [low, high](const Shape& s, uint64_t seed) {
            std::mt19937_64 generator(seed);
            std::uniform_real_distribution<float> value(low, high);
            std::vector<float> values(count(s));
            for (float& v : values) v = value(generator);
            return values;
          }};
}

InputDraw awayFromZero(Shape shape, float low, float high) {
  return {std::move(shape), [low, high](const Shape& s, uint64_t seed) {
            std::mt19937_64 generator(seed);
            std::uniform_real_distribution<float> magnitude(low, high);
            std::bernoulli_distribution negative(0.5);
            std::vector<float> values(count(s));
            for (float& v : values) v = negative(generator) ? -magnitude(generator) : magnitude(generator);
            return values;
          }};
}

InputDraw distinct(Shape shape, float low, float high) {
  return {std::move(shape), [low, high](const Shape& s, uint64_t seed) {
            std::vector<float> values(count(s));
            const double spacing = (static_cast<double>(high) - low) / static_cast<double>(std::max<std::size_t>(values.size(), 1));
            for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<float>(low + spacing * static_cast<double>(i));
            std::shuffle(values.begin(), values.end(), std::mt19937_64(seed));
            return values;
          }};
}

InputDraw lattice(Shape shape, float low, float high, float spacing, float phase) {
  return {std::move(shape), [low, high, spacing, phase](const Shape& s, uint64_t seed) {
            std::mt19937_64 generator(seed);
            const int steps = std::max(1, static_cast<int>(std::floor((high - low) / spacing - phase)));
            std::uniform_int_distribution<int> k(0, steps - 1);
            std::uniform_real_distribution<float> jitter(-spacing / 8, spacing / 8);
            std::vector<float> values(count(s));
            for (float& v : values) v = low + spacing * (static_cast<float>(k(generator)) + phase) + jitter(generator);
            return values;
          }};
}

InputDraw integers(Shape shape, int low, int high) {
  return {std::move(shape),
          [low, high](const Shape& s, uint64_t seed) {
            std::mt19937_64 generator(seed);
            std::uniform_int_distribution<int> value(low, high);
            std::vector<float> values(count(s));
            for (float& v : values) v = static_cast<float>(value(generator));
            return values;
          },
          false};
}

InputDraw constant(Shape shape, float value, bool differentiable) {
  return {std::move(shape), [value](const Shape& s, uint64_t) { return std::vector<float>(count(s), value); },
          differentiable};
}

}  // namespace smokesvd::draw

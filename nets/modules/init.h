// How a parameter is initialised, and the seeded generator behind it.
//
// Module::initialize(seed) draws every parameter of a module tree from a generator seeded by the seed and
// the parameter's dotted name (splitmix64 over the seed and a 64-bit FNV-1a hash of the name), so values
// do not depend on construction order, adding a module leaves the others' values unchanged, and the same
// seed gives the same numbers on every platform (the conversion to floats is written out, not left to
// the standard library's distributions).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace smokesvd::modules {

// Weights of convolutions and linear layers (fan_in = input channels x kernel elements):
//   He            U(-b, b), b = sqrt(6 / fan_in): Kaiming/He uniform for ReLU-like activations (gain sqrt 2,
//                 variance 2 / fan_in); biases 0. The default: it keeps activation variance through deep
//                 SiLU/ReLU stacks.
//   TorchDefault  U(-b, b), b = 1 / sqrt(fan_in) for weights and biases alike: what torch.nn.Conv*d and
//                 Linear do on construction (kaiming_uniform_ with a = sqrt 5), for exact parity of
//                 distributions with a freshly built PyTorch model.
//   Lecun         U(-b, b), b = sqrt(3 / fan_in), variance 1 / fan_in: keeps the variance of a linear map
//                 (skip connections and output heads without an activation in front); biases 0.
//   Zero          weights and biases 0: the last layer of a residual branch or of a denoiser, so that a
//                 fresh network starts as the identity (or predicts zero), as DDPM's zero-initialised convs.
enum class WeightInit { He, TorchDefault, Lecun, Zero };

// A parameter's rule: every value `value` (Constant), or uniform on [-bound, bound) (Uniform).
struct Init {
  enum class Kind { Constant, Uniform };
  Kind kind = Kind::Constant;
  double value = 0.0;  // Constant
  double bound = 0.0;  // Uniform

  static Init constant(double value) { return {Kind::Constant, value, 0.0}; }
  static Init uniform(double bound) { return {Kind::Uniform, 0.0, bound}; }
  // The weight and bias rules of `scheme` for a layer with the given fan-in.
  static Init weight(WeightInit scheme, int64_t fanIn);
  static Init bias(WeightInit scheme, int64_t fanIn);
};

// `count` values of `init` from the generator for (seed, name).
std::vector<float> drawValues(const Init& init, std::size_t count, uint64_t seed, const std::string& name);

}  // namespace smokesvd::modules

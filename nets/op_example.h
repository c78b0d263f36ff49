// Example inputs an op carries in its registration (OpSpec::examples). One test
// (tests/nets/op_driver_test.cpp, docs/nn-ops.md "Registering an op") runs every example of every op:
// into NaN-poisoned, guarded outputs; backward against central differences of the op's own forward;
// and through `smokesvd op`, which must give the same outputs. Every op needs at least one example,
// and together the examples must reach every shader no other test is listed for.
//
//   {.name = "3D, stride 2, padding 1",
//    .inputs = {{"x", draw::uniform({1, 3, 5, 6, 7})}, {"w", draw::uniform({4, 3, 3, 3, 3})}},
//    .attrs = {{"stride", "2"}, {"padding", "1"}}}
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "runtime/tensor.h"

namespace smokesvd {

// How one input's values are drawn: a function of its shape and a seed (same seed, same values).
using DrawValues = std::function<std::vector<float>(const Shape& shape, uint64_t seed)>;

struct InputDraw {
  Shape shape;
  DrawValues values;
  bool differentiable = true;  // false: data that is not differentiated (flags, timesteps)
};

namespace draw {

// Uniform in [low, high).
InputDraw uniform(Shape shape, float low = -1.0f, float high = 1.0f);
// |x| uniform in [low, high), either sign: inputs kept away from a kink at 0 (ReLU).
InputDraw awayFromZero(Shape shape, float low = 0.1f, float high = 1.0f);
// Every value different, evenly spaced over [low, high) and shuffled: no ties (max pooling).
InputDraw distinct(Shape shape, float low = -1.0f, float high = 1.0f);
// low + spacing (k + phase) for random k, plus jitter below spacing / 8: two inputs drawn with phases
// 0 and 0.5 stay at least spacing / 4 apart everywhere (|a - b| away from its kink at 0).
InputDraw lattice(Shape shape, float low, float high, float spacing, float phase);
// Whole numbers in [low, high], not differentiated (timesteps).
InputDraw integers(Shape shape, int low, int high);
// Every element `value`.
InputDraw constant(Shape shape, float value, bool differentiable = true);

}  // namespace draw

// The gradient check of an example: for a few probe directions d (dense random ones and single
// elements), <grad_x, d> against (<g, f(x + step d)> - <g, f(x - step d)>) / (2 step) with f the op's
// forward and g a random upstream gradient. They agree when the difference is within
// atol + rtol |<grad_x, d>| plus the float32 rounding floor of the two sums.
struct GradientCheck {
  double step = 1e-2;
  double rtol = 1e-3;
  double atol = 1e-6;
};

struct OpExample {
  std::string name;                          // what it exercises, e.g. "3D, stride 2, padding 1"
  std::map<std::string, InputDraw> inputs;   // every required input and the optional ones to give
  std::map<std::string, std::string> attrs;  // as --attr NAME=VALUE; the others keep their defaults
  GradientCheck gradient = {};               // used when the op has a backward
  // How far two runs of the same call may differ, relative to the largest magnitude of that output:
  // 0 (bit-identical) unless kernels add with atomics in whatever order the device runs them.
  double repeatTolerance = 0;
  bool noFloatAtomics = false;  // run as `smokesvd --no-float-atomics` (the compare-and-swap scatter paths)
  uint64_t seed = 1;            // of every draw (and of the upstream gradients and probes)
};

}  // namespace smokesvd

#include "nets/ops/conv_geometry.h"

#include <string>

#include "runtime/error.h"

namespace smokesvd::ops::conv {
namespace {

int64_t outputSize(int64_t input, int64_t kernel, const ConvParams& params) {
  const int64_t span = input + 2 * params.padding - kernel;
  return span < 0 ? 0 : span / params.stride + 1;
}

Shape spatialShape(int rank, int64_t leading0, int64_t leading1, const Int3& size) {
  if (rank == 4) return {leading0, leading1, size[1], size[2]};
  return {leading0, leading1, size[0], size[1], size[2]};
}

}  // namespace

Shape ConvGeometry::inputShape() const { return spatialShape(rank, batch, inChannels, input); }
Shape ConvGeometry::outputShape() const { return spatialShape(rank, batch, outChannels, output); }
Shape ConvGeometry::weightShape() const { return spatialShape(rank, outChannels, inChannels, kernel); }

ConvGeometry convGeometry(const char* op, const Shape& x, const Shape& w, const ConvParams& params) {
  const std::string prefix = std::string(op) + ": ";
  if (x.size() != 4 && x.size() != 5)
    throw Error(prefix + "input " + toString(x) + " must be [N, C, H, W] or [N, C, D, H, W]");
  if (w.size() != x.size())
    throw Error(prefix + "weight " + toString(w) + " must have the rank of the input " + toString(x));
  if (params.stride < 1) throw Error(prefix + "stride " + std::to_string(params.stride) + " must be >= 1");
  if (params.padding < 0) throw Error(prefix + "padding " + std::to_string(params.padding) + " must be >= 0");
  for (int64_t size : x)
    if (size < 1) throw Error(prefix + "input " + toString(x) + " has an empty axis");
  for (int64_t size : w)
    if (size < 1) throw Error(prefix + "weight " + toString(w) + " has an empty axis");
  if (w[1] != x[1])
    throw Error(prefix + "weight " + toString(w) + " expects " + std::to_string(w[1]) + " input channels, input " +
                toString(x) + " has " + std::to_string(x[1]));

  ConvGeometry g;
  g.rank = static_cast<int>(x.size());
  g.batch = x[0];
  g.inChannels = x[1];
  g.outChannels = w[0];
  const std::size_t first = x.size() - 3;  // index of D, or of the implied depth 1 before H
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const bool implied = g.rank == 4 && axis == 0;
    g.input[axis] = implied ? 1 : x[first + axis];
    g.kernel[axis] = implied ? 1 : w[first + axis];
  }
  g.stride = params.stride;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const bool implied = g.rank == 4 && axis == 0;
    g.padding[axis] = implied ? 0 : params.padding;
    g.output[axis] = implied ? 1 : outputSize(g.input[axis], g.kernel[axis], params);
    if (g.output[axis] < 1)
      throw Error(prefix + "kernel " + toString(w) + " with padding " + std::to_string(params.padding) +
                  " does not fit in input " + toString(x));
  }
  return g;
}

void requireShape(const char* op, const char* what, const Shape& actual, const Shape& expected) {
  if (actual != expected)
    throw Error(std::string(op) + ": " + what + " is " + toString(actual) + ", expected " + toString(expected));
}

Tensor as5d(const Tensor& tensor) {
  const Shape& s = tensor.shape();
  if (s.size() == 5) return tensor;
  return tensor.reshaped({s[0], s[1], 1, s[2], s[3]});
}

std::vector<Phase> transposedPhases(int64_t inputSize, int64_t kernel, int stride, int padding) {
  std::vector<Phase> phases;
  for (int64_t r = 0; r < stride && r < inputSize; ++r) {
    Phase p;
    p.phase = r;
    p.count = (inputSize - r + stride - 1) / stride;
    // Output i = r + stride*j receives tap k from gradient element o where i + padding = stride*o + k,
    // so k = (r + padding) mod stride + stride*u, o = j + (r + padding - k) / stride.
    const int64_t lowestTap = (r + padding) % stride;
    p.taps = lowestTap < kernel ? (kernel - lowestTap + stride - 1) / stride : 0;
    p.firstTap = lowestTap + stride * (p.taps - 1);
    // Taps run from firstTap down to lowestTap as t rises, reading gradient o = j + offset + t.
    p.offset = (r + padding - p.firstTap) / stride;
    if (p.taps == 0) p.offset = 0;
    phases.push_back(p);
  }
  return phases;
}

}  // namespace smokesvd::ops::conv

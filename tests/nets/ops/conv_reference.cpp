#include "tests/nets/ops/conv_reference.h"

#include <array>
#include <cstdint>

namespace smokesvd::testing {
namespace {

// A 4D or 5D shape as [a, b, D, H, W].
std::array<int64_t, 5> as5(const Shape& s) {
  if (s.size() == 4) return {s[0], s[1], 1, s[2], s[3]};
  return {s[0], s[1], s[2], s[3], s[4]};
}

// Padding and stride along z are neutral in 2D (depth 1, kernel depth 1).
int depthPadding(const Shape& s, const ConvSpec& spec) { return s.size() == 4 ? 0 : spec.padding; }

std::size_t at(const std::array<int64_t, 5>& s, int64_t a, int64_t b, int64_t z, int64_t y, int64_t x) {
  return static_cast<std::size_t>((((a * s[1] + b) * s[2] + z) * s[3] + y) * s[4] + x);
}

}  // namespace

Shape referenceConvOutputShape(const Shape& xShape, const Shape& wShape, const ConvSpec& spec) {
  Shape y{xShape[0], wShape[0]};
  for (std::size_t axis = 2; axis < xShape.size(); ++axis)
    y.push_back((xShape[axis] + 2 * spec.padding - wShape[axis]) / spec.stride + 1);
  return y;
}

Shape referenceConvTransposeOutputShape(const Shape& xShape, const Shape& wShape, const ConvSpec& spec) {
  Shape y{xShape[0], wShape[1]};
  for (std::size_t axis = 2; axis < xShape.size(); ++axis)
    y.push_back((xShape[axis] - 1) * spec.stride - 2 * spec.padding + wShape[axis] + spec.outputPadding);
  return y;
}

std::vector<double> convReference(std::span<const double> x, const Shape& xShape, std::span<const double> w,
                                  const Shape& wShape, std::span<const double> bias, const ConvSpec& spec) {
  const Shape yShape = referenceConvOutputShape(xShape, wShape, spec);
  const auto xs = as5(xShape), ws = as5(wShape), ys = as5(yShape);
  const int64_t pz = depthPadding(xShape, spec), p = spec.padding, s = spec.stride;
  std::vector<double> y(static_cast<std::size_t>(numElements(yShape)));
  for (int64_t n = 0; n < ys[0]; ++n)
    for (int64_t k = 0; k < ys[1]; ++k)
      for (int64_t oz = 0; oz < ys[2]; ++oz)
        for (int64_t oy = 0; oy < ys[3]; ++oy)
          for (int64_t ox = 0; ox < ys[4]; ++ox) {
            double sum = bias.empty() ? 0.0 : bias[static_cast<std::size_t>(k)];
            for (int64_t c = 0; c < xs[1]; ++c)
              for (int64_t r = 0; r < ws[2]; ++r)
                for (int64_t q = 0; q < ws[3]; ++q)
                  for (int64_t t = 0; t < ws[4]; ++t) {
                    const int64_t iz = oz * s - pz + r, iy = oy * s - p + q, ix = ox * s - p + t;
                    if (iz < 0 || iz >= xs[2] || iy < 0 || iy >= xs[3] || ix < 0 || ix >= xs[4]) continue;
                    sum += w[at(ws, k, c, r, q, t)] * x[at(xs, n, c, iz, iy, ix)];
                  }
            y[at(ys, n, k, oz, oy, ox)] = sum;
          }
  return y;
}

std::vector<double> convTransposeReference(std::span<const double> x, const Shape& xShape, std::span<const double> w,
                                           const Shape& wShape, std::span<const double> bias, const ConvSpec& spec) {
  const Shape yShape = referenceConvTransposeOutputShape(xShape, wShape, spec);
  const auto xs = as5(xShape), ws = as5(wShape), ys = as5(yShape);
  const int64_t pz = depthPadding(xShape, spec), p = spec.padding, s = spec.stride;
  std::vector<double> y(static_cast<std::size_t>(numElements(yShape)));
  for (int64_t n = 0; n < ys[0]; ++n)
    for (int64_t k = 0; k < ys[1]; ++k)
      for (int64_t i = 0; i < ys[2] * ys[3] * ys[4]; ++i)
        y[at(ys, n, k, 0, 0, 0) + static_cast<std::size_t>(i)] = bias.empty() ? 0.0 : bias[static_cast<std::size_t>(k)];
  for (int64_t n = 0; n < xs[0]; ++n)
    for (int64_t c = 0; c < xs[1]; ++c)
      for (int64_t iz = 0; iz < xs[2]; ++iz)
        for (int64_t iy = 0; iy < xs[3]; ++iy)
          for (int64_t ix = 0; ix < xs[4]; ++ix)
            for (int64_t k = 0; k < ws[1]; ++k)
              for (int64_t r = 0; r < ws[2]; ++r)
                for (int64_t q = 0; q < ws[3]; ++q)
                  for (int64_t t = 0; t < ws[4]; ++t) {
                    const int64_t oz = iz * s - pz + r, oy = iy * s - p + q, ox = ix * s - p + t;
                    if (oz < 0 || oz >= ys[2] || oy < 0 || oy >= ys[3] || ox < 0 || ox >= ys[4]) continue;
                    y[at(ys, n, k, oz, oy, ox)] += x[at(xs, n, c, iz, iy, ix)] * w[at(ws, c, k, r, q, t)];
                  }
  return y;
}

std::vector<double> convWeightGradReference(std::span<const double> x, const Shape& xShape,
                                            std::span<const double> dy, const Shape& wShape, const ConvSpec& spec) {
  const Shape yShape = referenceConvOutputShape(xShape, wShape, spec);
  const auto xs = as5(xShape), ws = as5(wShape), ys = as5(yShape);
  const int64_t pz = depthPadding(xShape, spec), p = spec.padding, s = spec.stride;
  std::vector<double> dw(static_cast<std::size_t>(numElements(wShape)));
  for (int64_t k = 0; k < ws[0]; ++k)
    for (int64_t c = 0; c < ws[1]; ++c)
      for (int64_t r = 0; r < ws[2]; ++r)
        for (int64_t q = 0; q < ws[3]; ++q)
          for (int64_t t = 0; t < ws[4]; ++t) {
            double sum = 0;
            for (int64_t n = 0; n < ys[0]; ++n)
              for (int64_t oz = 0; oz < ys[2]; ++oz)
                for (int64_t oy = 0; oy < ys[3]; ++oy)
                  for (int64_t ox = 0; ox < ys[4]; ++ox) {
                    const int64_t iz = oz * s - pz + r, iy = oy * s - p + q, ix = ox * s - p + t;
                    if (iz < 0 || iz >= xs[2] || iy < 0 || iy >= xs[3] || ix < 0 || ix >= xs[4]) continue;
                    sum += dy[at(ys, n, k, oz, oy, ox)] * x[at(xs, n, c, iz, iy, ix)];
                  }
            dw[at(ws, k, c, r, q, t)] = sum;
          }
  return dw;
}

}  // namespace smokesvd::testing

#include "nets/ops/resample.h"

#include <algorithm>
#include <numeric>

#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr uint32_t kWorkgroup = 64;
constexpr int64_t kQuadsPerInvocation = 4;  // SEGMENT in resample_rows.comp

void requireShape(const char* op, const char* name, const Tensor& tensor, const Shape& expected) {
  if (tensor.shape() != expected)
    throw Error(std::string(op) + ": " + name + " has shape " + toString(tensor.shape()) + ", expected " +
                toString(expected));
}

int64_t product(const Shape& shape, std::size_t begin, std::size_t end) {
  return std::accumulate(shape.begin() + static_cast<std::ptrdiff_t>(begin),
                         shape.begin() + static_cast<std::ptrdiff_t>(end), int64_t{1}, std::multiplies<>());
}

// The spatial axes in the order the forward resamples them: W first when upsampling (its gathering
// kernel then runs on the smallest tensor), W last when downsampling.
std::vector<std::size_t> forwardAxes(const Shape& shape, const Resample& resample) {
  std::vector<std::size_t> axes;
  for (std::size_t axis = shape.size(); axis-- > 2;) axes.push_back(axis);
  if (resample.down) std::reverse(axes.begin(), axes.end());
  return axes;
}

// The sizes of one pass along an axis: n inputs and m outputs along it, `rows` rows written (for W: the
// rows of the tensor; for H or D: (outer index, index along the axis)) of `rowLength` elements each.
struct AxisPass {
  int32_t n, m;
  int64_t inner, rows, rowLength;
  bool fastest;
};

AxisPass axisPass(std::size_t axis, const Shape& input, const Shape& output, const Shape& written) {
  AxisPass pass{static_cast<int32_t>(input[axis]), static_cast<int32_t>(output[axis]),
                product(input, axis + 1, input.size()), 0, 0, axis + 1 == input.size()};
  pass.rows = product(written, 0, pass.fastest ? axis : axis + 1);
  pass.rowLength = pass.fastest ? written[axis] : pass.inner;
  return pass;
}

std::vector<int32_t> constants(const Resample& resample, bool backward, bool aligned) {
  return {static_cast<int32_t>(resample.mode), resample.down ? 1 : 0, resample.factor, backward ? 1 : 0,
          aligned ? 1 : 0};
}

// Along H or D: whole rows combined as vec4s (shaders/nn/resample_rows.comp).
void rowsPass(Stream& stream, const Resample& resample, bool backward, const AxisPass& pass, const Tensor& from,
              const Tensor& to) {
  const bool aligned = pass.inner % 4 == 0;
  const int64_t quadsPerRow = (pass.inner + 3) / 4;
  const int64_t segmentsPerRow = (quadsPerRow + kQuadsPerInvocation - 1) / kQuadsPerInvocation;
  const uint64_t items = static_cast<uint64_t>(pass.rows * segmentsPerRow);
  struct { int32_t n, m, inner, quadsPerRow, segmentsPerRow; uint32_t items; } push{
      pass.n, pass.m, static_cast<int32_t>(pass.inner), static_cast<int32_t>(quadsPerRow),
      static_cast<int32_t>(segmentsPerRow), static_cast<uint32_t>(items)};
  const Kernel& kernel = stream.kernel("nn/resample_rows", {kWorkgroup, 1, 1}, constants(resample, backward, aligned));
  stream.dispatchFlat(kernel, {aligned ? asVec4(from) : Arg(from), to}, push, items);
}

// Along W by gathering scalars (shaders/nn/resample_x.comp).
void gatherPass(Stream& stream, const Resample& resample, bool backward, const AxisPass& pass, const Tensor& from,
                const Tensor& to) {
  const int64_t quadsPerRow = (pass.rowLength + 3) / 4;
  const uint64_t items = static_cast<uint64_t>(pass.rows * quadsPerRow);
  struct { int32_t n, m, quadsPerRow; uint32_t items; } push{pass.n, pass.m, static_cast<int32_t>(quadsPerRow),
                                                            static_cast<uint32_t>(items)};
  const Kernel& kernel =
      stream.kernel("nn/resample_x", {kWorkgroup, 1, 1}, constants(resample, backward, pass.rowLength % 4 == 0));
  stream.dispatchFlat(kernel, {from, to}, push, items);
}

// The transpose of upsampling along W for widths divisible by 4, reading whole gy texels
// (shaders/nn/resample_up_backward_x.comp).
void upsampleTransposeW(Stream& stream, const Resample& resample, const AxisPass& pass, const Tensor& gy,
                        const Tensor& gx) {
  const uint64_t items = static_cast<uint64_t>(pass.rows * (pass.n / 4));
  struct { int32_t texelsPerRow; uint32_t items; } push{pass.n / 4, static_cast<uint32_t>(items)};
  const Kernel& kernel = stream.kernel("nn/resample_up_backward_x", {kWorkgroup, 1, 1},
                                       {static_cast<int32_t>(resample.mode), resample.factor});
  stream.dispatchFlat(kernel, {asVec4(gy), gx}, push, items);
}

// The transpose of upsampling along H or D for rows divisible by 4, reading every gy row once
// (shaders/nn/resample_up_backward_rows.comp).
void upsampleTransposeRows(Stream& stream, const Resample& resample, const AxisPass& pass, const Tensor& gy,
                           const Tensor& gx) {
  constexpr int64_t kRun = 8;  // RUN in the shader
  const int64_t outer = pass.rows / pass.n;
  const int64_t runs = (pass.n + kRun - 1) / kRun;
  const uint64_t items = static_cast<uint64_t>(outer * runs * (pass.inner / 4));
  struct { int32_t n, quadsPerRow, runs; uint32_t items; } push{pass.n, static_cast<int32_t>(pass.inner / 4),
                                                                static_cast<int32_t>(runs), static_cast<uint32_t>(items)};
  const Kernel& kernel = stream.kernel("nn/resample_up_backward_rows", {kWorkgroup, 1, 1},
                                       {static_cast<int32_t>(resample.mode), resample.factor});
  stream.dispatchFlat(kernel, {asVec4(gy), gx}, push, items);
}

// One pass along `axis`: forward reads `from` (size n along the axis) and writes `to` (size m);
// backward reads the gradient of size m and writes that of size n.
void resampleAxis(Stream& stream, const Resample& resample, bool backward, std::size_t axis, const Tensor& from,
                  const Tensor& to) {
  const Shape& input = backward ? to.shape() : from.shape();
  const Shape& output = backward ? from.shape() : to.shape();
  const AxisPass pass = axisPass(axis, input, output, to.shape());
  const bool upsampleTranspose = backward && !resample.down;
  if (!pass.fastest && upsampleTranspose && pass.inner % 4 == 0) upsampleTransposeRows(stream, resample, pass, from, to);
  else if (!pass.fastest) rowsPass(stream, resample, backward, pass, from, to);
  else if (upsampleTranspose && pass.n % 4 == 0) upsampleTransposeW(stream, resample, pass, from, to);
  else gatherPass(stream, resample, backward, pass, from, to);
}

// Upsampling of inputs whose width is a multiple of 4, in one pass (shaders/nn/resample_up.comp).
void upsampleAligned(Stream& stream, const Resample& resample, const Tensor& x, const Tensor& y) {
  const Shape& in = x.shape();
  const Shape& out = y.shape();
  const bool volume = in.size() == 5;
  const int32_t inW = static_cast<int32_t>(in.back()), inH = static_cast<int32_t>(in[in.size() - 2]);
  const int32_t inD = volume ? static_cast<int32_t>(in[2]) : 1, outD = volume ? static_cast<int32_t>(out[2]) : 1;
  // cells of outputs that read the same input rows: n + 1 along an axis (linear), n (nearest), 1 (2D depth)
  const int32_t extra = resample.mode == ResampleMode::Linear ? 1 : 0;
  const int32_t cellsY = inH + extra, cellsZ = volume ? inD + extra : 1;
  const uint64_t items = static_cast<uint64_t>(in[0] * in[1] * cellsZ * cellsY * (inW / 4));
  struct {
    int32_t inSize[3], texelsPerRow, outSize[3];
    uint32_t items;
    int32_t cells[2];
  } push{{inW, inH, inD}, inW / 4, {static_cast<int32_t>(out.back()), static_cast<int32_t>(out[out.size() - 2]), outD},
         static_cast<uint32_t>(items), {cellsY, cellsZ}};
  const Kernel& kernel = stream.kernel("nn/resample_up", {kWorkgroup, 1, 1},
                                       {static_cast<int32_t>(resample.mode), resample.factor, volume ? 3 : 2});
  stream.dispatchFlat(kernel, {asVec4(x), y}, push, items);
}

}  // namespace

Shape resampledShape(const Shape& x, const Resample& resample) {
  const bool spatial = (x.size() == 4 || x.size() == 5) &&
                       std::all_of(x.begin(), x.end(), [](int64_t s) { return s >= 1; });
  if (!spatial) throw Error("resample: expected a non-empty N,C,H,W or N,C,D,H,W tensor, got " + toString(x));
  if (resample.factor < 1)
    throw Error("resample: the factor must be at least 1, got " + std::to_string(resample.factor));
  Shape out = x;
  for (std::size_t axis = 2; axis < out.size(); ++axis) {
    out[axis] = resample.down ? x[axis] / resample.factor : x[axis] * resample.factor;
    if (out[axis] < 1)
      throw Error("resample: downsampling " + toString(x) + " by " + std::to_string(resample.factor) +
                  " leaves an empty axis");
  }
  return out;
}

void resampleForward(Stream& stream, const Resample& resample, const Tensor& x, const Tensor& y) {
  const Shape target = resampledShape(x.shape(), resample);
  requireShape("resample", "y", y, target);
  if (!resample.down && x.shape().back() % 4 == 0) {
    upsampleAligned(stream, resample, x, y);
    return;
  }
  const std::vector<std::size_t> axes = forwardAxes(x.shape(), resample);
  Tensor current = x;
  for (std::size_t step = 0; step < axes.size(); ++step) {
    Shape shape = current.shape();
    shape[axes[step]] = target[axes[step]];
    const Tensor next = step + 1 == axes.size() ? y : Tensor(stream.context(), shape);
    resampleAxis(stream, resample, false, axes[step], current, next);
    current = next;
  }
}

void resampleBackward(Stream& stream, const Resample& resample, const Tensor& gy, const Tensor& gx) {
  requireShape("resample backward", "gy", gy, resampledShape(gx.shape(), resample));
  std::vector<std::size_t> axes = forwardAxes(gx.shape(), resample);
  std::reverse(axes.begin(), axes.end());
  Tensor current = gy;
  for (std::size_t step = 0; step < axes.size(); ++step) {
    Shape shape = current.shape();
    shape[axes[step]] = gx.shape()[axes[step]];
    const Tensor next = step + 1 == axes.size() ? gx : Tensor(stream.context(), shape);
    resampleAxis(stream, resample, true, axes[step], current, next);
    current = next;
  }
}

}  // namespace smokesvd::ops

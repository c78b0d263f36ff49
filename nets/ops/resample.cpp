#include "nets/ops/resample.h"

#include <algorithm>

#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{16, 4, 1};
constexpr int64_t kMaxGroups = 65535;

struct Push {
  int32_t inSize[3];  // (W, H, D)
  int32_t layers;
  int32_t outSize[3];
};

// (W, H, D) of a 4D or 5D shape; D = 1 for 4D.
std::array<int32_t, 3> spatialSize(const Shape& shape) {
  const std::size_t r = shape.size();
  return {static_cast<int32_t>(shape[r - 1]), static_cast<int32_t>(shape[r - 2]),
          static_cast<int32_t>(r == 5 ? shape[2] : 1)};
}

void requireShape(const char* op, const char* name, const Tensor& tensor, const Shape& expected) {
  if (tensor.shape() != expected)
    throw Error(std::string(op) + ": " + name + " has shape " + toString(tensor.shape()) + ", expected " +
                toString(expected));
}

// Records the kernel that writes `written` (y forward, gx backward) from `source`.
void run(Stream& stream, const Resample& resample, bool backward, const Shape& in, const Shape& out,
         const Tensor& source, const Tensor& written) {
  const auto inSize = spatialSize(in);
  const auto outSize = spatialSize(out);
  const auto& size = backward ? inSize : outSize;
  const int64_t layers = in[0] * in[1] * size[2];
  const Push push{{inSize[0], inSize[1], inSize[2]}, static_cast<int32_t>(layers), {outSize[0], outSize[1], outSize[2]}};
  const Kernel& kernel =
      stream.kernel("nn/resample", kWorkgroup,
                    {static_cast<int32_t>(resample.mode), resample.down ? 1 : 0, resample.factor,
                     static_cast<int32_t>(in.size()) - 2, backward ? 1 : 0});
  stream.dispatch(kernel, {source, written}, push,
                  {static_cast<uint32_t>((size[0] + kWorkgroup[0] - 1) / kWorkgroup[0]),
                   static_cast<uint32_t>((size[1] + kWorkgroup[1] - 1) / kWorkgroup[1]),
                   static_cast<uint32_t>(std::min(layers, kMaxGroups))});
}

}  // namespace

Shape resampledShape(const Shape& x, const Resample& resample) {
  const bool spatial = (x.size() == 4 || x.size() == 5) &&
                       std::all_of(x.begin(), x.end(), [](int64_t s) { return s >= 1; });
  if (!spatial) throw Error("resample: expected a non-empty N,C,H,W or N,C,D,H,W tensor, got " + toString(x));
  if (resample.factor < 1) throw Error("resample: the factor must be at least 1, got " + std::to_string(resample.factor));
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
  requireShape("resample", "y", y, resampledShape(x.shape(), resample));
  run(stream, resample, false, x.shape(), y.shape(), x, y);
}

void resampleBackward(Stream& stream, const Resample& resample, const Tensor& gy, const Tensor& gx) {
  requireShape("resample backward", "gy", gy, resampledShape(gx.shape(), resample));
  run(stream, resample, true, gx.shape(), gy.shape(), gy, gx);
}

}  // namespace smokesvd::ops

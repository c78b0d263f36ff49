#include "nets/ops/pool.h"

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

void requireSpatial(const char* op, const Shape& shape) {
  const bool ok = (shape.size() == 4 || shape.size() == 5) &&
                  std::all_of(shape.begin(), shape.end(), [](int64_t s) { return s >= 1; });
  if (!ok) throw Error(std::string(op) + ": expected a non-empty N,C,H,W or N,C,D,H,W tensor, got " + toString(shape));
}

// (W, H, D) of a 4D or 5D shape; D = 1 for 4D.
std::array<int32_t, 3> spatialSize(const Shape& shape) {
  const std::size_t r = shape.size();
  return {static_cast<int32_t>(shape[r - 1]), static_cast<int32_t>(shape[r - 2]),
          static_cast<int32_t>(r == 5 ? shape[2] : 1)};
}

// Binds (source, gy, out) over the pooling of `in` to `outShape`.
void run(Stream& stream, PoolKind kind, bool backward, const Shape& in, const Shape& outShape, const Tensor& source,
         const Tensor& gy, const Tensor& out) {
  const auto inSize = spatialSize(in);
  const auto outSize = spatialSize(outShape);
  const int64_t layers = in[0] * in[1] * outSize[2];
  const Push push{{inSize[0], inSize[1], inSize[2]}, static_cast<int32_t>(layers), {outSize[0], outSize[1], outSize[2]}};
  const int32_t dims = static_cast<int32_t>(in.size()) - 2;
  const Kernel& kernel =
      stream.kernel("nn/pool", kWorkgroup, {kind == PoolKind::Max ? 1 : 0, dims, backward ? 1 : 0});
  stream.dispatch(kernel, {source, gy, out}, push,
                  {static_cast<uint32_t>((outSize[0] + kWorkgroup[0] - 1) / kWorkgroup[0]),
                   static_cast<uint32_t>((outSize[1] + kWorkgroup[1] - 1) / kWorkgroup[1]),
                   static_cast<uint32_t>(std::min(layers, kMaxGroups))});
}

void requireShape(const char* op, const char* name, const Tensor& tensor, const Shape& expected) {
  if (tensor.shape() != expected)
    throw Error(std::string(op) + ": " + name + " has shape " + toString(tensor.shape()) + ", expected " +
                toString(expected));
}

}  // namespace

Shape pooledShape(const Shape& x) {
  requireSpatial("pool", x);
  Shape out = x;
  for (std::size_t axis = 2; axis < out.size(); ++axis) out[axis] = (x[axis] + 1) / 2;
  return out;
}

void poolForward(Stream& stream, PoolKind kind, const Tensor& x, const Tensor& y) {
  requireShape("pool", "y", y, pooledShape(x.shape()));
  run(stream, kind, false, x.shape(), y.shape(), x, x, y);  // the gy binding is unused forward
}

void poolBackward(Stream& stream, PoolKind kind, const Tensor& x, const Tensor& gy, const Tensor& gx) {
  requireShape("pool backward", "gy", gy, pooledShape(x.shape()));
  requireShape("pool backward", "gx", gx, x.shape());
  // average pooling binds gy in place of x, which it does not read
  run(stream, kind, true, x.shape(), gy.shape(), kind == PoolKind::Max ? x : gy, gy, gx);
}

}  // namespace smokesvd::ops

#include "nets/ops/pool.h"

#include <algorithm>

#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr uint32_t kWorkgroup = 64;
constexpr int64_t kQuadsPerInvocation = 4;  // SEGMENT in pool.comp

void requireSpatial(const char* op, const Shape& shape) {
  const bool ok = (shape.size() == 4 || shape.size() == 5) &&
                  std::all_of(shape.begin(), shape.end(), [](int64_t s) { return s >= 1; });
  if (!ok) throw Error(std::string(op) + ": expected a non-empty N,C,H,W or N,C,D,H,W tensor, got " + toString(shape));
}

void requireShape(const char* op, const char* name, const Tensor& tensor, const Shape& expected) {
  if (tensor.shape() != expected)
    throw Error(std::string(op) + ": " + name + " has shape " + toString(tensor.shape()) + ", expected " +
                toString(expected));
}

// (W, H, D) of a 4D or 5D shape; D = 1 for 4D.
std::array<int32_t, 3> spatialSize(const Shape& shape) {
  const std::size_t r = shape.size();
  return {static_cast<int32_t>(shape[r - 1]), static_cast<int32_t>(shape[r - 2]),
          static_cast<int32_t>(r == 5 ? shape[2] : 1)};
}

// Binds (source, gy, out) over the pooling of `in` to `out`; `source` is x, or any tensor when unread.
void run(Stream& stream, PoolKind kind, bool backward, const Shape& in, const Shape& out, const Tensor& source,
         const Tensor& gy, const Tensor& result) {
  const auto inSize = spatialSize(in);
  const auto outSize = spatialSize(out);
  const int64_t quadsPerRow = (outSize[0] + 3) / 4;
  const int64_t segmentsPerRow = (quadsPerRow + kQuadsPerInvocation - 1) / kQuadsPerInvocation;
  const int64_t rows = in[0] * in[1] * outSize[2] * outSize[1];
  const uint64_t items = static_cast<uint64_t>(rows * segmentsPerRow);
  const bool aligned = inSize[0] % 8 == 0;
  struct {
    int32_t inSize[3], quadsPerRow, outSize[3], segmentsPerRow;
    uint32_t items;
  } push{{inSize[0], inSize[1], inSize[2]}, static_cast<int32_t>(quadsPerRow), {outSize[0], outSize[1], outSize[2]},
         static_cast<int32_t>(segmentsPerRow), static_cast<uint32_t>(items)};
  const Kernel& kernel = stream.kernel("nn/pool", {kWorkgroup, 1, 1},
                                       {kind == PoolKind::Max ? 1 : 0, static_cast<int32_t>(in.size()) - 2,
                                        backward ? 1 : 0, aligned ? 1 : 0});
  const Arg sourceArg = aligned ? asVec4(source) : Arg(source);
  const Arg gyArg = aligned ? asVec4(gy) : Arg(gy);
  stream.dispatchFlat(kernel, {sourceArg, gyArg, result}, push, items);
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

#include "nets/ops/linear.h"

#include <array>

#include "nets/ops/reduce_axes.h"
#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr uint32_t kTileRows = 8;     // rows of C per invocation (shaders/nn/matmul.comp)
constexpr uint32_t kTileColumns = 4;  // columns of C per invocation
// 8 x 8 invocations: 8 SIMD lanes along columns, sharing rows; a workgroup covers 64 rows x 32 columns.
constexpr std::array<uint32_t, 3> kWorkgroup{8, 8, 1};

uint32_t tiles(int64_t extent, uint32_t tile) { return static_cast<uint32_t>((extent + tile - 1) / tile); }

void requireRank2(const char* what, const Tensor& t) {
  if (t.rank() != 2) throw Error(std::string("matmul: ") + what + " must be a matrix, got " + toString(t.shape()));
}

// x [..., in] seen as [rows, in]
Tensor rows(const Tensor& x, int64_t features, const char* what) {
  if (x.rank() < 1 || x.size(-1) != features)
    throw Error(std::string("linear: ") + what + " " + toString(x.shape()) + " must end in " +
                std::to_string(features) + " features");
  return x.reshaped({x.numel() / features, features});
}

void requireWeight(const Tensor& w) {
  if (w.rank() != 2) throw Error("linear: the weight must be [out, in], got " + toString(w.shape()));
}

}  // namespace

void matmul(Stream& stream, const Tensor& a, bool transposeA, const Tensor& b, bool transposeB, const Tensor* bias,
            const Tensor& c) {
  requireRank2("a", a);
  requireRank2("b", b);
  requireRank2("c", c);
  const int64_t M = transposeA ? a.size(1) : a.size(0);
  const int64_t K = transposeA ? a.size(0) : a.size(1);
  const int64_t N = transposeB ? b.size(0) : b.size(1);
  const int64_t bK = transposeB ? b.size(1) : b.size(0);
  if (bK != K || c.shape() != Shape{M, N})
    throw Error("matmul: a " + toString(a.shape()) + (transposeA ? "^T" : "") + " times b " + toString(b.shape()) +
                (transposeB ? "^T" : "") + " into c " + toString(c.shape()) + ": the shapes do not chain");
  if (bias && bias->numel() != N)
    throw Error("matmul: the bias " + toString(bias->shape()) + " must have " + std::to_string(N) + " elements");
  if (M == 0 || N == 0) return;
  if (K == 0) {
    if (bias) throw Error("matmul: an empty inner dimension with a bias is not supported");
    stream.fillZero(c);
    return;
  }
  // Each operand is read as vec4 texels when its fastest extent is a multiple of 4.
  const bool vec4A = (transposeA ? M : K) % 4 == 0;
  const bool vec4B = (transposeB ? K : N) % 4 == 0;
  const Kernel& kernel = stream.kernel("nn/matmul", kWorkgroup,
                                       {transposeA ? 1 : 0, transposeB ? 1 : 0, vec4A ? 1 : 0, vec4B ? 1 : 0,
                                        bias ? 1 : 0});
  struct { uint32_t M, N, K; } push{static_cast<uint32_t>(M), static_cast<uint32_t>(N), static_cast<uint32_t>(K)};
  stream.dispatch(kernel, {vec4A ? asVec4(a) : Arg(a), vec4B ? asVec4(b) : Arg(b), bias ? *bias : a, c}, push,
                  {tiles(tiles(N, kTileColumns), kWorkgroup[0]), tiles(tiles(M, kTileRows), kWorkgroup[1]), 1});
}

void linearForward(Stream& stream, const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y) {
  requireWeight(w);
  const Tensor x2 = rows(x, w.size(1), "input");
  const Tensor y2 = rows(y, w.size(0), "output");
  if (x2.size(0) != y2.size(0))
    throw Error("linear: input " + toString(x.shape()) + " and output " + toString(y.shape()) + " differ in rows");
  matmul(stream, x2, false, w, true, bias, y2);
}

void linearBackwardInput(Stream& stream, const Tensor& gy, const Tensor& w, const Tensor& gx) {
  requireWeight(w);
  matmul(stream, rows(gy, w.size(0), "output gradient"), false, w, false, nullptr, rows(gx, w.size(1), "input gradient"));
}

void linearBackwardWeight(Stream& stream, const Tensor& gy, const Tensor& x, const Tensor& gw) {
  requireWeight(gw);
  matmul(stream, rows(gy, gw.size(0), "output gradient"), true, rows(x, gw.size(1), "input"), false, nullptr, gw);
}

void linearBackwardBias(Stream& stream, const Tensor& gy, const Tensor& gb) {
  const Tensor gy2 = rows(gy, gb.numel(), "output gradient");
  const int axes[] = {0};
  reduceAxes(stream, ReduceMap::Identity, gy2, nullptr, axes, 1.0f, gb);
}

}  // namespace smokesvd::ops

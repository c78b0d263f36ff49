#include "nets/ops/broadcast.h"

#include <algorithm>
#include <array>
#include <bit>

#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr uint32_t kWorkgroupSize = 128;
constexpr int kCopy = 4;  // OP of shaders/nn/broadcast_binary.comp: y = a

Shape alignedTo(const Shape& shape, std::size_t rank) {
  Shape result(rank - shape.size(), 1);
  result.insert(result.end(), shape.begin(), shape.end());
  return result;
}

// The output as [D0, D1, D2, D3] with, per operand, its strides along D0..D2 and whether it runs along D3.
struct Plan {
  std::array<uint64_t, 4> extents{1, 1, 1, 1};
  std::array<uint64_t, 3> stridesA{}, stridesB{};
  bool innerA = true, innerB = true;
};

Plan plan(const Shape& a, const Shape& b, const Shape& out) {
  struct Run {
    bool fullA, fullB;
    uint64_t extent;
  };
  const Shape alignedA = alignedTo(a, out.size()), alignedB = alignedTo(b, out.size());
  std::vector<Run> runs;
  for (std::size_t axis = 0; axis < out.size(); ++axis) {
    if (out[axis] == 1) continue;
    const Run run{alignedA[axis] != 1, alignedB[axis] != 1, static_cast<uint64_t>(out[axis])};
    if (!runs.empty() && runs.back().fullA == run.fullA && runs.back().fullB == run.fullB)
      runs.back().extent *= run.extent;
    else
      runs.push_back(run);
  }
  if (runs.size() > 4)
    throw Error("broadcast of " + toString(a) + " and " + toString(b) + ": more than 4 runs of axes that broadcast alike");
  runs.insert(runs.begin(), 4 - runs.size(), Run{true, true, 1});
  Plan result;
  uint64_t strideA = 1, strideB = 1;
  for (int d = 3; d >= 0; --d) {
    result.extents[d] = runs[d].extent;
    if (d < 3) {
      result.stridesA[d] = runs[d].fullA ? strideA : 0;
      result.stridesB[d] = runs[d].fullB ? strideB : 0;
    }
    if (runs[d].fullA) strideA *= runs[d].extent;
    if (runs[d].fullB) strideB *= runs[d].extent;
  }
  result.innerA = runs[3].fullA;
  result.innerB = runs[3].fullB;
  return result;
}

void dispatch(Stream& stream, int op, const Tensor& a, const Tensor& b, const Tensor& y) {
  const Plan p = plan(a.shape(), b.shape(), y.shape());
  const bool fullA = a.numel() == y.numel(), fullB = b.numel() == y.numel();
  const bool vec4 = p.extents[3] % 4 == 0;
  const int inner = (p.innerA ? 1 : 0) | (p.innerB ? 2 : 0);
  const Kernel& kernel = stream.kernel("nn/broadcast_binary", {kWorkgroupSize, 1, 1},
                                       {op, inner, fullA ? 1 : 0, fullB ? 1 : 0, vec4 ? 1 : 0});
  const auto u32 = [](uint64_t v) { return static_cast<uint32_t>(v); };
  const FastDivisor byD1 = fastDivisor(u32(p.extents[1])), byD2 = fastDivisor(u32(p.extents[2])),
                    byD3 = fastDivisor(u32(p.extents[3]));
  struct {
    uint32_t n, D1, D2, D3;
    FastDivisor byD1, byD2, byD3;
    uint32_t sa0, sa1, sa2, sb0, sb1, sb2;
  } push{u32(y.numel()), u32(p.extents[1]), u32(p.extents[2]), u32(p.extents[3]), byD1, byD2, byD3,
         u32(p.stridesA[0]), u32(p.stridesA[1]), u32(p.stridesA[2]), u32(p.stridesB[0]), u32(p.stridesB[1]),
         u32(p.stridesB[2])};
  // Operands read whole vec4 texels where they are y-shaped, or run along an aligned last axis.
  const auto bind = [&](const Tensor& t, bool full, bool runs) { return full || (vec4 && runs) ? asVec4(t) : Arg(t); };
  stream.dispatchFlat(kernel, {bind(a, fullA, p.innerA), bind(b, fullB, p.innerB), y}, push,
                      (static_cast<uint64_t>(y.numel()) + 3) / 4);
}

}  // namespace

Shape broadcastShape(const char* op, const Shape& a, const Shape& b) {
  const std::size_t rank = std::max(a.size(), b.size());
  const Shape alignedA = alignedTo(a, rank), alignedB = alignedTo(b, rank);
  Shape result(rank);
  for (std::size_t axis = 0; axis < rank; ++axis) {
    if (alignedA[axis] != alignedB[axis] && alignedA[axis] != 1 && alignedB[axis] != 1)
      throw Error(std::string(op) + ": shapes " + toString(a) + " and " + toString(b) + " do not broadcast");
    result[axis] = alignedA[axis] == 1 ? alignedB[axis] : alignedA[axis];
  }
  return result;
}

FastDivisor fastDivisor(uint32_t d) {
  if (d == 0) throw Error("fast divisor: division by zero");
  const uint32_t shift = static_cast<uint32_t>(std::bit_width(d) - 1);
  if ((d & (d - 1)) == 0) return {0, shift};
  return {static_cast<uint32_t>((uint64_t{1} << (32 + shift)) / d + 1), shift};
}

std::vector<int> broadcastAxes(const Shape& operand, const Shape& output) {
  const Shape aligned = alignedTo(operand, output.size());
  std::vector<int> axes;
  for (std::size_t axis = 0; axis < output.size(); ++axis)
    if (aligned[axis] == 1 && output[axis] != 1) axes.push_back(static_cast<int>(axis));
  return axes;
}

void broadcastBinary(Stream& stream, BinaryOp op, const Tensor& a, const Tensor& b, const Tensor& y) {
  const Shape out = broadcastShape("broadcast op", a.shape(), b.shape());
  if (y.shape() != out)
    throw Error("broadcast op: the output " + toString(y.shape()) + " must have the broadcast shape " + toString(out));
  if (y.numel() == 0) return;
  dispatch(stream, static_cast<int>(op), a, b, y);
}

void expand(Stream& stream, const Tensor& x, const Tensor& y) {
  if (x.rank() > y.rank() || broadcastShape("expand", x.shape(), y.shape()) != y.shape())
    throw Error("expand: " + toString(x.shape()) + " does not broadcast to " + toString(y.shape()));
  if (y.numel() == 0) return;
  dispatch(stream, kCopy, x, x, y);
}

}  // namespace smokesvd::ops

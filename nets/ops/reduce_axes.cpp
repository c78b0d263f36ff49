#include "nets/ops/reduce_axes.h"

#include <algorithm>
#include <array>

#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{64, 1, 1};
constexpr uint64_t kBusyInvocations = 1024;  // below this many outputs, reduced runs are split in chunks
constexpr uint64_t kMinChunk = 128;          // elements one partial sums at least

std::string axesText(std::span<const int> axes) {
  std::string text;
  for (int axis : axes) text += (text.empty() ? "" : ", ") + std::to_string(axis);
  return "{" + text + "}";
}

// The input seen as [K2, R1, K1, R0, K0]: kept and reduced runs of axes, innermost last.
struct Collapsed {
  std::array<uint64_t, 5> extents{1, 1, 1, 1, 1};  // K2, R1, K1, R0, K0
  uint64_t kept() const { return extents[0] * extents[2] * extents[4]; }
  uint64_t reduced() const { return extents[1] * extents[3]; }
};

Collapsed collapse(const Shape& shape, std::span<const int> axes) {
  std::vector<std::pair<bool, uint64_t>> runs;  // (reduced, extent), outermost first
  for (int axis = 0; axis < static_cast<int>(shape.size()); ++axis) {
    if (shape[axis] == 1) continue;
    const bool reduced = std::find(axes.begin(), axes.end(), axis) != axes.end();
    if (!runs.empty() && runs.back().first == reduced)
      runs.back().second *= static_cast<uint64_t>(shape[axis]);
    else
      runs.emplace_back(reduced, static_cast<uint64_t>(shape[axis]));
  }
  Collapsed result;
  int slot = 4;  // K0; kept runs take even slots, reduced runs odd ones
  for (auto run = runs.rbegin(); run != runs.rend(); ++run) {
    if (run->first == (slot % 2 == 0)) --slot;  // a reduced run innermost leaves K0 = 1
    if (slot < 0)
      throw Error("reduce over axes " + axesText(axes) + " of " + toString(shape) +
                  ": the reduced axes form more than two separate runs");
    result.extents[slot--] = run->second;
  }
  return result;
}

struct Push {
  uint32_t K2, R1, K1, R0, K0, chunk, partials;
  float scale;
};

void dispatchPass(Stream& stream, ReduceMap map, const Tensor& a, const Tensor& b, const Collapsed& c,
                  uint64_t chunk, uint64_t partials, float scale, const Tensor& out) {
  const bool vec4 = c.extents[4] == 1 && c.extents[3] % 4 == 0 && chunk % 4 == 0;
  const Kernel& kernel = stream.kernel("nn/reduce_axes", kWorkgroup, {static_cast<int32_t>(map), vec4 ? 1 : 0});
  const auto u32 = [](uint64_t v) { return static_cast<uint32_t>(v); };
  const Push push{u32(c.extents[0]), u32(c.extents[1]), u32(c.extents[2]), u32(c.extents[3]), u32(c.extents[4]),
                  u32(chunk),        u32(partials),     scale};
  const Arg argA = vec4 ? asVec4(a) : Arg(a);
  const Arg argB = vec4 ? asVec4(b) : Arg(b);
  stream.dispatchFlat(kernel, {argA, argB, out}, push, c.kept() * partials);
}

}  // namespace

std::vector<int> normalizeAxes(const char* op, std::span<const int> axes, const Shape& shape) {
  const int rank = static_cast<int>(shape.size());
  std::vector<int> result;
  for (int axis : axes) {
    const int resolved = axis < 0 ? axis + rank : axis;
    if (resolved < 0 || resolved >= rank)
      throw Error(std::string(op) + ": axis " + std::to_string(axis) + " is out of range for " + toString(shape));
    if (std::find(result.begin(), result.end(), resolved) != result.end())
      throw Error(std::string(op) + ": axis " + std::to_string(axis) + " is given twice for " + toString(shape));
    result.push_back(resolved);
  }
  std::sort(result.begin(), result.end());
  return result;
}

Shape reducedShape(const Shape& shape, std::span<const int> axes, bool keepdims) {
  Shape result;
  for (int axis = 0; axis < static_cast<int>(shape.size()); ++axis) {
    const bool reduced = std::find(axes.begin(), axes.end(), axis) != axes.end();
    if (!reduced)
      result.push_back(shape[axis]);
    else if (keepdims)
      result.push_back(1);
  }
  return result;
}

int64_t reducedCount(const Shape& shape, std::span<const int> axes) {
  int64_t count = 1;
  for (int axis : axes) count *= shape[axis];
  return count;
}

std::vector<int> allAxes(int rank) {
  std::vector<int> axes(rank);
  for (int axis = 0; axis < rank; ++axis) axes[axis] = axis;
  return axes;
}

void reduceAxes(Stream& stream, ReduceMap map, const Tensor& a, const Tensor* b, std::span<const int> axes,
                float scale, const Tensor& y) {
  const bool needsB = map == ReduceMap::Difference || map == ReduceMap::SquaredDifference ||
                      map == ReduceMap::AbsoluteDifference;
  if (needsB && (!b || b->shape() != a.shape()))
    throw Error("reduce: the second input must have the first's shape " + toString(a.shape()) +
                (b ? ", got " + toString(b->shape()) : ", got none"));
  if (a.numel() == 0) throw Error("reduce: the input " + toString(a.shape()) + " is empty");
  const Collapsed c = collapse(a.shape(), axes);
  if (static_cast<uint64_t>(y.numel()) != c.kept())
    throw Error("reduce over axes " + axesText(axes) + " of " + toString(a.shape()) + ": the output " +
                toString(y.shape()) + " must hold " + std::to_string(c.kept()) + " elements");
  const Tensor& second = needsB ? *b : a;

  const uint64_t outputs = c.kept();
  const uint64_t reduced = c.reduced();
  const bool vec4Runs = c.extents[4] == 1 && c.extents[3] % 4 == 0;
  uint64_t partials = 1;
  if (outputs < kBusyInvocations && reduced >= 2 * kMinChunk)
    partials = std::min((kBusyInvocations + outputs - 1) / outputs, reduced / kMinChunk);
  uint64_t chunk = (reduced + partials - 1) / partials;
  if (vec4Runs) chunk = (chunk + 3) / 4 * 4;
  partials = (reduced + chunk - 1) / chunk;
  if (partials == 1) {
    dispatchPass(stream, map, a, second, c, chunk, 1, scale, y);
    return;
  }
  Tensor sums(stream.context(), {static_cast<int64_t>(partials * outputs)});
  dispatchPass(stream, map, a, second, c, chunk, partials, 1.0f, sums);
  Collapsed overPartials;
  overPartials.extents = {1, 1, 1, partials, outputs};
  dispatchPass(stream, ReduceMap::Identity, sums, sums, overPartials, partials, 1, scale, y);
}

}  // namespace smokesvd::ops

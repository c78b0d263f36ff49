// Sums over chosen axes (torch.sum(x, dim=axes)), with an elementwise map of one or two inputs fused
// in front so that losses reduce (a - b)^2 or |a - b| without a temporary. One kernel pass, plus a
// second over partial sums when there are few outputs to share the work among.
//
// Supported: any axes whose reduced runs, after dropping size-1 axes and merging neighbours, form at
// most two separate runs (e.g. N and H,W of N,C,H,W; C and H of N,C,D,H,W). More is an Error.
#pragma once

#include <span>
#include <vector>

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

// What is summed: a, a - b, (a - b)^2, |a - b| or a^2 (b has a's shape; Identity and Square ignore it).
enum class ReduceMap { Identity = 0, Difference = 1, SquaredDifference = 2, AbsoluteDifference = 3, Square = 4 };

// Axes counted from the end when negative, sorted, without repeats; Error naming `op` and the shape if
// an axis is out of range or repeated.
std::vector<int> normalizeAxes(const char* op, std::span<const int> axes, const Shape& shape);
// `shape` with the (normalised) axes set to 1 (keepdims) or removed.
Shape reducedShape(const Shape& shape, std::span<const int> axes, bool keepdims);
// The number of elements each output sums: the product of the reduced extents.
int64_t reducedCount(const Shape& shape, std::span<const int> axes);
std::vector<int> allAxes(int rank);

// y = scale * sum over `axes` of map(a, b). `axes` are normalised (normalizeAxes); an empty list
// reduces nothing (y = scale * map(a, b)). y may have any shape with the right number of elements.
void reduceAxes(Stream& stream, ReduceMap map, const Tensor& a, const Tensor* b, std::span<const int> axes,
                float scale, const Tensor& y);

}  // namespace smokesvd::ops

#include "nets/ops/concat.h"

#include "nets/ops/broadcast.h"
#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr uint32_t kWorkgroupSize = 128;

// Elements per channel: the product of the axes after 1.
int64_t spatial(const Shape& shape) {
  int64_t count = 1;
  for (std::size_t axis = 2; axis < shape.size(); ++axis) count *= shape[axis];
  return count;
}

void requireChannels(const char* op, const Shape& shape) {
  if (shape.size() < 2) throw Error(std::string(op) + ": " + toString(shape) + " has no channel axis (rank < 2)");
}

bool sameExceptChannels(const Shape& a, const Shape& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t axis = 0; axis < a.size(); ++axis)
    if (axis != 1 && a[axis] != b[axis]) return false;
  return true;
}

}  // namespace

Shape concatShape(std::span<const Shape> shapes) {
  if (shapes.empty()) throw Error("concat: no inputs");
  Shape result = shapes.front();
  requireChannels("concat", result);
  for (std::size_t i = 1; i < shapes.size(); ++i) {
    if (!sameExceptChannels(shapes[i], result))
      throw Error("concat: input " + std::to_string(i) + " " + toString(shapes[i]) + " differs from input 0 " +
                  toString(shapes.front()) + " outside axis 1");
    result[1] += shapes[i][1];
  }
  return result;
}

void copyChannels(Stream& stream, const Tensor& source, int64_t from, const Tensor& destination, int64_t to,
                  int64_t count) {
  requireChannels("channel copy", source.shape());
  requireChannels("channel copy", destination.shape());
  if (!sameExceptChannels(source.shape(), destination.shape()) || from < 0 || to < 0 || count < 0 ||
      from + count > source.size(1) || to + count > destination.size(1))
    throw Error("channel copy of " + std::to_string(count) + " channels from " + std::to_string(from) + " of " +
                toString(source.shape()) + " to " + std::to_string(to) + " of " + toString(destination.shape()) +
                ": out of range or shapes differ outside axis 1");
  const int64_t s = spatial(source.shape());
  const int64_t total = source.size(0) * count * s;
  if (total == 0) return;
  const auto u32 = [](int64_t v) { return static_cast<uint32_t>(v); };
  struct {
    uint32_t total, srcRow, srcOffset, dstRow, dstOffset, length;
    FastDivisor byLength;
  } push{u32(total), u32(source.size(1) * s), u32(from * s), u32(destination.size(1) * s), u32(to * s), u32(count * s),
         fastDivisor(u32(count * s))};
  const bool vec4 = push.srcRow % 4 == 0 && push.srcOffset % 4 == 0 && push.dstRow % 4 == 0 &&
                    push.dstOffset % 4 == 0 && push.length % 4 == 0;
  const Kernel& kernel = stream.kernel("nn/concat_channels", {kWorkgroupSize, 1, 1}, {vec4 ? 1 : 0});
  stream.dispatchFlat(kernel, {vec4 ? asVec4(source) : Arg(source), destination}, push,
                      (static_cast<uint64_t>(total) + 3) / 4);
}

void concatChannels(Stream& stream, std::span<const Tensor> inputs, const Tensor& y) {
  std::vector<Shape> shapes;
  for (const Tensor& input : inputs) shapes.push_back(input.shape());
  const Shape expected = concatShape(shapes);
  if (y.shape() != expected)
    throw Error("concat: the output " + toString(y.shape()) + " must be " + toString(expected));
  int64_t offset = 0;
  for (const Tensor& input : inputs) {
    copyChannels(stream, input, 0, y, offset, input.size(1));
    offset += input.size(1);
  }
}

void sliceChannels(Stream& stream, const Tensor& x, int64_t begin, int64_t end, const Tensor& y) {
  requireChannels("slice", x.shape());
  if (begin < 0 || end < begin || end > x.size(1))
    throw Error("slice: channels [" + std::to_string(begin) + ", " + std::to_string(end) + ") are not within " +
                toString(x.shape()));
  Shape expected = x.shape();
  expected[1] = end - begin;
  if (y.shape() != expected) throw Error("slice: the output " + toString(y.shape()) + " must be " + toString(expected));
  copyChannels(stream, x, begin, y, 0, end - begin);
}

}  // namespace smokesvd::ops

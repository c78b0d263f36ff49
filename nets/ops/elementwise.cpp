#include "nets/ops/elementwise.h"

#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{128, 1, 1};

uint32_t count(const Tensor& tensor) { return static_cast<uint32_t>(tensor.numel()); }
uint64_t vec4Items(const Tensor& tensor) { return (static_cast<uint64_t>(tensor.numel()) + 3) / 4; }

}  // namespace

void requireSameShape(const char* op, std::initializer_list<const Tensor*> tensors) {
  const Shape& first = (*tensors.begin())->shape();
  for (const Tensor* tensor : tensors) {
    if (tensor->shape() != first)
      throw Error(std::string(op) + ": shapes differ, " + toString(first) + " and " + toString(tensor->shape()));
  }
}

void fill(Stream& stream, const Tensor& y, float value) {
  struct { uint32_t n; float value; } push{count(y), value};
  stream.dispatchFlat(stream.kernel("tensor/fill", kWorkgroup), {y}, push, vec4Items(y));
}

void copy(Stream& stream, const Tensor& x, const Tensor& y) {
  if (x.numel() != y.numel())
    throw Error("copy: " + toString(x.shape()) + " and " + toString(y.shape()) + " have different element counts");
  struct { uint32_t n; } push{count(y)};
  stream.dispatchFlat(stream.kernel("tensor/copy", kWorkgroup), {asVec4(x), y}, push, vec4Items(y));
}

void binary(Stream& stream, BinaryOp op, const Tensor& a, const Tensor& b, const Tensor& y) {
  requireSameShape("binary op", {&a, &b, &y});
  struct { uint32_t n; } push{count(y)};
  const Kernel& kernel = stream.kernel("tensor/binary", kWorkgroup, {static_cast<int32_t>(op)});
  stream.dispatchFlat(kernel, {asVec4(a), asVec4(b), y}, push, vec4Items(y));
}

void axpby(Stream& stream, float alpha, const Tensor& x, float beta, const Tensor& y, const Tensor& out) {
  requireSameShape("axpby", {&x, &y, &out});
  struct { uint32_t n; float alpha, beta; } push{count(out), alpha, beta};
  stream.dispatchFlat(stream.kernel("tensor/axpby", kWorkgroup), {asVec4(x), asVec4(y), out}, push, vec4Items(out));
}

}  // namespace smokesvd::ops

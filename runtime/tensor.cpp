#include "runtime/tensor.h"

#include "runtime/context.h"
#include "runtime/error.h"
#include "runtime/tensor_guards.h"

namespace smokesvd {

std::string toString(const Shape& shape) {
  std::string text = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  return text + "]";
}

int64_t numElements(const Shape& shape) {
  int64_t count = 1;
  for (int64_t extent : shape)
    if (__builtin_mul_overflow(count, extent, &count))
      throw Error("shape " + toString(shape) + " has more elements than a 64-bit count holds");
  return count;
}

Tensor::Tensor(Context& context, Shape shape) : context_(&context), shape_(std::move(shape)) {
  for (int64_t extent : shape_)
    if (extent < 0) throw Error("tensor " + toString(shape_) + ": dimensions must not be negative");
  TensorGuards* guards = context.tensorGuards();
  buffer_ = context.buffers().acquire(guards ? TensorGuards::guardedBytes(bytes()) : bytes(), "tensor " + toString(shape_));
  if (guards) guards->arm(*this);
}

uint64_t Tensor::boundBytes() const {
  return context_ && context_->tensorGuards() ? TensorGuards::guardedBytes(bytes()) : bytes();
}

Tensor Tensor::fromHost(Context& context, Shape shape, std::span<const float> values) {
  Tensor tensor(context, std::move(shape));
  tensor.upload(values);
  return tensor;
}

int64_t Tensor::size(int axis) const {
  const int resolved = axis < 0 ? axis + rank() : axis;
  if (resolved < 0 || resolved >= rank())
    throw Error("axis " + std::to_string(axis) + " is out of range for tensor " + toString(shape_));
  return shape_[resolved];
}

Shape Tensor::strides() const {
  Shape strides(shape_.size());
  int64_t stride = 1;
  for (int axis = rank() - 1; axis >= 0; --axis) {
    strides[axis] = stride;
    stride *= shape_[axis];
  }
  return strides;
}

Tensor Tensor::reshaped(Shape shape) const {
  if (numElements(shape) != numel())
    throw Error("cannot reshape tensor " + toString(shape_) + " to " + toString(shape) + ": element counts differ");
  Tensor view = *this;
  view.shape_ = std::move(shape);
  return view;
}

Tensor Tensor::constantDerived(const std::string& key) const {
  const Buffer::Derived* kept = buffer_->derived(key);
  if (!kept) return {};
  Tensor derived;
  derived.context_ = context_;
  derived.shape_ = kept->shape;
  derived.buffer_ = kept->buffer;
  return derived;
}

void Tensor::keepConstantDerived(const std::string& key, const Tensor& derived) const {
  buffer_->keepDerived(key, {derived.shape_, derived.buffer_});
}

void Tensor::upload(std::span<const float> values) const {
  if (static_cast<int64_t>(values.size()) != numel())
    throw Error("upload to tensor " + toString(shape_) + ": got " + std::to_string(values.size()) +
                " values, expected " + std::to_string(numel()));
  try {
    buffer_->write(values.data(), bytes());
  } catch (const Error& error) {
    throw Error("upload to tensor " + toString(shape_) + ": " + error.what());
  }
}

std::vector<float> Tensor::download() const {
  std::vector<float> values(static_cast<std::size_t>(numel()));
  buffer_->read(values.data(), bytes());
  return values;
}

}  // namespace smokesvd

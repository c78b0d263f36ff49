// Float32 tensors: a shape in PyTorch order (N,C,H,W or N,C,D,H,W; the last axis is fastest) over a
// pooled device buffer. Copying a Tensor shares the buffer; the buffer returns to the pool when the
// last Tensor using it is gone.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "runtime/buffer.h"

namespace smokesvd {

class Context;

using Shape = std::vector<int64_t>;

std::string toString(const Shape& shape);  // "[2, 3, 4]"
int64_t numElements(const Shape& shape);  // throws Error if the count overflows 64 bits

class Tensor {
 public:
  Tensor() = default;
  // Uninitialised contents. Throws Error if a dimension is negative or the tensor is larger than one
  // storage buffer may span on the device.
  Tensor(Context& context, Shape shape);
  static Tensor fromHost(Context& context, Shape shape, std::span<const float> values);

  bool defined() const { return buffer_ != nullptr; }
  Context& context() const { return *context_; }
  const Shape& shape() const { return shape_; }
  int rank() const { return static_cast<int>(shape_.size()); }
  int64_t size(int axis) const;  // negative axes count from the end
  int64_t numel() const { return numElements(shape_); }
  uint64_t bytes() const { return static_cast<uint64_t>(numel()) * sizeof(float); }
  // Bytes a storage binding of this tensor spans: bytes(), or in a guarded context (runtime/tensor_guards.h)
  // its elements rounded up to vec4s plus the guard.
  uint64_t boundBytes() const;
  Shape strides() const;  // contiguous strides, in elements

  // The same buffer seen with another shape of the same number of elements.
  Tensor reshaped(Shape shape) const;

  Buffer& buffer() const { return *buffer_; }
  const std::shared_ptr<Buffer>& sharedBuffer() const { return buffer_; }

  void upload(std::span<const float> values) const;  // values.size() must equal numel()
  std::vector<float> download() const;

  // Frozen weights: no stream may write this tensor's buffer any more (Buffer::markConstant), so tensors
  // derived from it by recorded commands may be kept with it across recordings (a convolution's packed
  // weights), until the host writes it. constantDerived is undefined where nothing is kept under `key`.
  void markConstant() const { buffer_->markConstant(); }
  bool constant() const { return buffer_->constant(); }
  Tensor constantDerived(const std::string& key) const;
  void keepConstantDerived(const std::string& key, const Tensor& derived) const;

 private:
  Context* context_ = nullptr;
  Shape shape_;
  std::shared_ptr<Buffer> buffer_;
};

}  // namespace smokesvd

// Elementwise tensor kernels on flat float32 data (no broadcasting; see nets/ops for broadcasting ops).
// Each records one dispatch into the stream; outputs may alias inputs.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

enum class BinaryOp { Add = 0, Sub = 1, Mul = 2, Div = 3 };

void fill(Stream& stream, const Tensor& y, float value);                     // y = value
void copy(Stream& stream, const Tensor& x, const Tensor& y);                 // y = x
void binary(Stream& stream, BinaryOp op, const Tensor& a, const Tensor& b, const Tensor& y);  // y = a op b
inline void add(Stream& s, const Tensor& a, const Tensor& b, const Tensor& y) { binary(s, BinaryOp::Add, a, b, y); }
inline void mul(Stream& s, const Tensor& a, const Tensor& b, const Tensor& y) { binary(s, BinaryOp::Mul, a, b, y); }
void axpby(Stream& stream, float alpha, const Tensor& x, float beta, const Tensor& y, const Tensor& out);  // out = αx + βy
inline void axpy(Stream& s, float alpha, const Tensor& x, const Tensor& y) { axpby(s, alpha, x, 1.0f, y, y); }  // y += αx
inline void scale(Stream& s, const Tensor& x, float alpha, const Tensor& y) { axpby(s, alpha, x, 0.0f, x, y); }  // y = αx

// Throws Error naming `op` unless every tensor has the shape of the first.
void requireSameShape(const char* op, std::initializer_list<const Tensor*> tensors);

}  // namespace smokesvd::ops

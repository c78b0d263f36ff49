// Differentiable elementwise ops with broadcasting (autograd wrappers of nets/ops/broadcast.h), and reshape.
//
//   Var broadcastBinary(Tape& tape, ops::BinaryOp op, const Var& a, const Var& b);
//     y = a op b with NumPy/PyTorch broadcasting (shapes aligned at the last axis): a + b, a - b, a * b, a / b.
//   Var channelBinary(Tape& tape, ops::BinaryOp op, const Var& x, const Var& v);
//     x [N, C, ...] op v, v holding C values (one per channel, any shape: [C], [1, C, 1, 1], ...) or N*C
//     values (per sample and channel: [N, C], a timestep embedding); v is read as [1 or N, C, 1, ..., 1].
//   Var sampleBinary(Tape& tape, ops::BinaryOp op, const Var& x, const Var& w);
//     x [N, ...] op w, w holding N values (one per sample: [N] or [N, 1, 1, 1]), e.g. per-sample loss weights.
//   Var addChannel(tape, x, v), mulChannel(tape, x, v), mulSample(tape, x, w): the common cases above.
//   Var reshape(Tape& tape, const Var& x, Shape shape);
//     the same values with another shape of as many elements (a view; the gradient is reshaped back).
//
// Gradients: the upstream gradient (times b, 1/b or -a/b^2 for mul and div) summed over the axes along
// which each operand was repeated, so it has the operand's own shape.
// Registered for `smokesvd op` as "broadcast" (a, b), "channel_broadcast" (x, v), "sample_broadcast"
// (x, w), each with attribute op = add | sub | mul | div, and "reshape" (x; shape = comma list).
#pragma once

#include "nets/autograd/tape.h"
#include "nets/ops/elementwise.h"

namespace smokesvd::fn {

Var broadcastBinary(Tape& tape, ops::BinaryOp op, const Var& a, const Var& b);
Var channelBinary(Tape& tape, ops::BinaryOp op, const Var& x, const Var& v);
Var sampleBinary(Tape& tape, ops::BinaryOp op, const Var& x, const Var& w);
inline Var addChannel(Tape& tape, const Var& x, const Var& v) { return channelBinary(tape, ops::BinaryOp::Add, x, v); }
inline Var mulChannel(Tape& tape, const Var& x, const Var& v) { return channelBinary(tape, ops::BinaryOp::Mul, x, v); }
inline Var mulSample(Tape& tape, const Var& x, const Var& w) { return sampleBinary(tape, ops::BinaryOp::Mul, x, w); }
Var reshape(Tape& tape, const Var& x, Shape shape);

}  // namespace smokesvd::fn

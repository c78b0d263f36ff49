#include "nets/functional/broadcast.h"

#include "nets/op_registry.h"
#include "nets/ops/broadcast.h"
#include "nets/ops/reduce_axes.h"
#include "runtime/error.h"

namespace smokesvd::fn {
namespace {

// The gradient of an operand read with shape `view` (which broadcast to g's shape): g summed over the
// repeated axes, times `scale`.
Tensor reduceTo(Tape& t, const Tensor& g, const Shape& view, float scale) {
  const std::vector<int> axes = ops::broadcastAxes(view, g.shape());
  if (axes.empty() && scale == 1.0f) return g.reshaped(view);
  Tensor result(t.context(), view);
  ops::reduceAxes(t.stream(), ops::ReduceMap::Identity, g, nullptr, axes, scale, result);
  return result;
}

void accumulateViewed(Tape& t, const Var& input, const Tensor& gradient) {
  t.accumulate(input, gradient.reshaped(input->value.shape()));
}

// y = a op b where a and b are read with the shapes viewA and viewB (same element counts as their values).
Var binary(Tape& tape, ops::BinaryOp op, const Var& a, const Shape& viewA, const Var& b, const Shape& viewB) {
  const Tensor va = a->value.reshaped(viewA), vb = b->value.reshaped(viewB);
  Tensor y(tape.context(), ops::broadcastShape("broadcast op", viewA, viewB));
  ops::broadcastBinary(tape.stream(), op, va, vb, y);
  Var out = tape.output(y, {a, b});
  if (!out->requiresGrad) return out;
  tape.record({out}, [op, a, b, va, vb, out](Tape& t) {
    const Tensor g = t.grad(out);
    const Tensor& result = out->value;
    // d/da: g (add, sub), g b (mul), g / b (div)
    if (a->requiresGrad) {
      Tensor ga = g;
      if (op == ops::BinaryOp::Mul || op == ops::BinaryOp::Div) {
        ga = Tensor(t.context(), result.shape());
        ops::broadcastBinary(t.stream(), op, g, vb, ga);
      }
      accumulateViewed(t, a, reduceTo(t, ga, va.shape(), 1.0f));
    }
    // d/db: g (add), -g (sub), g a (mul), -g a / b^2 = -(g y) / b (div)
    if (b->requiresGrad) {
      Tensor gb = g;
      float sign = op == ops::BinaryOp::Sub ? -1.0f : 1.0f;
      if (op == ops::BinaryOp::Mul) {
        gb = Tensor(t.context(), result.shape());
        ops::broadcastBinary(t.stream(), ops::BinaryOp::Mul, g, va, gb);
      } else if (op == ops::BinaryOp::Div) {
        Tensor gy(t.context(), result.shape());
        ops::mul(t.stream(), g, result, gy);
        gb = Tensor(t.context(), result.shape());
        ops::broadcastBinary(t.stream(), ops::BinaryOp::Div, gy, vb, gb);
        sign = -1.0f;
      }
      accumulateViewed(t, b, reduceTo(t, gb, vb.shape(), sign));
    }
  });
  return out;
}

// [1 or N, C, 1, ..., 1] (rank of x) for a vector of C or N*C values.
Shape channelView(const Shape& x, int64_t values, const char* op) {
  if (x.size() < 2) throw Error(std::string(op) + ": " + toString(x) + " has no channel axis");
  Shape view(x.size(), 1);
  view[1] = x[1];
  if (values == x[0] * x[1] && values != x[1]) view[0] = x[0];
  else if (values != x[1])
    throw Error(std::string(op) + ": " + std::to_string(values) + " values are neither one per channel (" +
                std::to_string(x[1]) + ") nor one per sample and channel of " + toString(x));
  return view;
}

}  // namespace

Var broadcastBinary(Tape& tape, ops::BinaryOp op, const Var& a, const Var& b) {
  return binary(tape, op, a, a->value.shape(), b, b->value.shape());
}

Var channelBinary(Tape& tape, ops::BinaryOp op, const Var& x, const Var& v) {
  return binary(tape, op, x, x->value.shape(), v, channelView(x->value.shape(), v->value.numel(), "channel op"));
}

Var sampleBinary(Tape& tape, ops::BinaryOp op, const Var& x, const Var& w) {
  const Shape& shape = x->value.shape();
  if (shape.empty() || w->value.numel() != shape[0])
    throw Error("sample op: " + toString(w->value.shape()) + " must hold one value per sample of " + toString(shape));
  Shape view(shape.size(), 1);
  view[0] = shape[0];
  return binary(tape, op, x, shape, w, view);
}

Var reshape(Tape& tape, const Var& x, Shape shape) {
  Var out = tape.output(x->value.reshaped(std::move(shape)), {x});
  if (out->requiresGrad)
    tape.record({out}, [x, out](Tape& t) { t.accumulate(x, t.grad(out).reshaped(x->value.shape())); });
  return out;
}

namespace {

ops::BinaryOp parseOp(const OpAttrs& attrs) {
  const std::string name = attrs.text("op");
  if (name == "add") return ops::BinaryOp::Add;
  if (name == "sub") return ops::BinaryOp::Sub;
  if (name == "mul") return ops::BinaryOp::Mul;
  if (name == "div") return ops::BinaryOp::Div;
  throw Error("attribute op='" + name + "' is not one of add, sub, mul, div");
}

const AttrSpec kOpAttr{"op", "add", "add, sub, mul or div"};

const bool registered =
    registerOp({"broadcast", "y = a op b with NumPy broadcasting", {"a", "b"}, {}, {kOpAttr}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{broadcastBinary(t, parseOp(attrs), in[0], in[1])};
                },
                {{.name = "add, b repeated along the last axis",
                  .inputs = {{"a", draw::uniform({2, 3, 5})}, {"b", draw::uniform({3, 1})}},
                  .attrs = {{"op", "add"}}},
                 {.name = "sub, a repeated along a leading axis",
                  .inputs = {{"a", draw::uniform({3, 7})}, {"b", draw::uniform({2, 3, 7})}},
                  .attrs = {{"op", "sub"}}},
                 {.name = "mul, 4-aligned rows", .inputs = {{"a", draw::uniform({2, 3, 8})}, {"b", draw::uniform({1, 3, 8})}},
                  .attrs = {{"op", "mul"}}},
                 {.name = "div, both repeated",
                  .inputs = {{"a", draw::uniform({2, 1, 5})}, {"b", draw::uniform({3, 1}, 0.5f, 2.0f)}},
                  .attrs = {{"op", "div"}}}}}) &&
    registerOp({"channel_broadcast", "y = x op v, v one value per channel (or per sample and channel)", {"x", "v"}, {},
                {kOpAttr}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{channelBinary(t, parseOp(attrs), in[0], in[1])};
                },
                {{.name = "mul, one value per channel",
                  .inputs = {{"x", draw::uniform({2, 3, 5, 7})}, {"v", draw::uniform({3})}},
                  .attrs = {{"op", "mul"}}},
                 {.name = "add, one value per sample and channel, volume",
                  .inputs = {{"x", draw::uniform({2, 3, 2, 3, 4})}, {"v", draw::uniform({2, 3})}},
                  .attrs = {{"op", "add"}}}}}) &&
    registerOp({"sample_broadcast", "y = x op w, w one value per sample", {"x", "w"}, {}, {kOpAttr}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{sampleBinary(t, parseOp(attrs), in[0], in[1])};
                },
                {{.name = "mul", .inputs = {{"x", draw::uniform({3, 2, 5})}, {"w", draw::uniform({3})}},
                  .attrs = {{"op", "mul"}}},
                 {.name = "div", .inputs = {{"x", draw::uniform({2, 3, 4, 5})}, {"w", draw::uniform({2, 1, 1, 1}, 0.5f, 2.0f)}},
                  .attrs = {{"op", "div"}}}}}) &&
    registerOp({"reshape", "y = x with another shape of as many elements", {"x"}, {},
                {{"shape", "", "comma-separated extents"}}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  const std::vector<int64_t> extents = attrs.integers("shape");
                  return std::vector<Var>{reshape(t, in[0], Shape(extents.begin(), extents.end()))};
                },
                {{.name = "[2, 3, 5] as [5, 6]", .inputs = {{"x", draw::uniform({2, 3, 5})}}, .attrs = {{"shape", "5,6"}},
                  .gradient = {.step = 0.25}}}});

}  // namespace
}  // namespace smokesvd::fn

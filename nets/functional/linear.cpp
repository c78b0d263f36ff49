#include "nets/functional/linear.h"

#include "nets/op_registry.h"
#include "nets/ops/linear.h"
#include "runtime/error.h"

namespace smokesvd::fn {

Var linear(Tape& tape, const Var& x, const Var& w, const Var& b) {
  if (w->value.rank() != 2) throw Error("linear: the weight must be [out, in], got " + toString(w->value.shape()));
  Shape shape = x->value.shape();
  if (shape.empty()) throw Error("linear: the input must have a feature axis, got a scalar");
  shape.back() = w->value.size(0);
  Tensor y(tape.context(), shape);
  ops::linearForward(tape.stream(), x->value, w->value, b ? &b->value : nullptr, y);
  Var out = tape.output(y, {x, w, b});
  if (out->requiresGrad) {
    tape.record({out}, [x, w, b, out](Tape& t) {
      const Tensor g = t.grad(out);
      if (x->requiresGrad) {
        Tensor gx(t.context(), x->value.shape());
        ops::linearBackwardInput(t.stream(), g, w->value, gx);
        t.accumulate(x, gx);
      }
      if (w->requiresGrad) {
        Tensor gw(t.context(), w->value.shape());
        ops::linearBackwardWeight(t.stream(), g, x->value, gw);
        t.accumulate(w, gw);
      }
      if (b && b->requiresGrad) {
        Tensor gb(t.context(), b->value.shape());
        ops::linearBackwardBias(t.stream(), g, gb);
        t.accumulate(b, gb);
      }
    });
  }
  return out;
}

namespace {

const bool registered = registerOp(
    {"linear", "y = x W^T + b (W [out, in], x [..., in])", {"x", "w"}, {"b"}, {}, {"y"},
     [](Tape& t, const std::vector<Var>& in, const OpAttrs&) { return std::vector<Var>{linear(t, in[0], in[1], in[2])}; },
     {{.name = "odd sizes, bias",
       .inputs = {{"x", draw::uniform({3, 5})}, {"w", draw::uniform({7, 5})}, {"b", draw::uniform({7})}},
       .gradient = {.step = 0.25}},
      {.name = "leading axes, 4-aligned features, no bias",
       .inputs = {{"x", draw::uniform({2, 3, 8})}, {"w", draw::uniform({4, 8})}},
       .gradient = {.step = 0.25}}}});

}  // namespace
}  // namespace smokesvd::fn

#include "nets/functional/activation.h"

#include "nets/op_registry.h"
#include "nets/ops/activation.h"

namespace smokesvd::fn {
namespace {

Var activate(Tape& tape, const Var& x, ops::Activation activation, float negativeSlope) {
  Tensor y(tape.context(), x->value.shape());
  ops::activationForward(tape.stream(), activation, negativeSlope, x->value, y);
  Var out = tape.output(y, {x});
  if (out->requiresGrad) {
    tape.record({out}, [x, out, activation, negativeSlope](Tape& t) {
      Tensor gx(t.context(), x->value.shape());
      ops::activationBackward(t.stream(), activation, negativeSlope, x->value, t.grad(out), gx);
      t.accumulate(x, gx);
    });
  }
  return out;
}

}  // namespace

Var relu(Tape& tape, const Var& x) { return activate(tape, x, ops::Activation::Relu, 0.0f); }
Var leakyRelu(Tape& tape, const Var& x, float negativeSlope) {
  return activate(tape, x, ops::Activation::LeakyRelu, negativeSlope);
}
Var silu(Tape& tape, const Var& x) { return activate(tape, x, ops::Activation::Silu, 0.0f); }
Var sigmoid(Tape& tape, const Var& x) { return activate(tape, x, ops::Activation::Sigmoid, 0.0f); }
Var tanh(Tape& tape, const Var& x) { return activate(tape, x, ops::Activation::Tanh, 0.0f); }

namespace {

using Apply = std::function<std::vector<Var>(Tape&, const std::vector<Var>&, const OpAttrs&)>;

Apply unary(Var (*op)(Tape&, const Var&)) {
  return [op](Tape& t, const std::vector<Var>& in, const OpAttrs&) { return std::vector<Var>{op(t, in[0])}; };
}

// Odd and 4-aligned shapes; inputs of ReLU and leaky ReLU away from their kink at 0.
std::vector<OpExample> examples(bool kinked, std::map<std::string, std::string> attrs = {}) {
  auto x = [kinked](Shape shape) { return kinked ? draw::awayFromZero(std::move(shape)) : draw::uniform(std::move(shape), -4, 4); };
  return {{.name = "odd shape", .inputs = {{"x", x({2, 3, 5, 7})}}, .attrs = attrs},
          {.name = "4-aligned shape", .inputs = {{"x", x({2, 8})}}, .attrs = attrs}};
}

const bool registered =
    registerOp({"relu", "y = max(x, 0)", {"x"}, {}, {}, {"y"}, unary(relu), examples(true)}) &&
    registerOp({"leaky_relu", "y = x > 0 ? x : negative_slope * x", {"x"}, {},
                {{"negative_slope", "0.01", "slope for x <= 0"}}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{leakyRelu(t, in[0], static_cast<float>(attrs.number("negative_slope")))};
                },
                examples(true, {{"negative_slope", "0.2"}})}) &&
    registerOp({"silu", "y = x * sigmoid(x)", {"x"}, {}, {}, {"y"}, unary(silu), examples(false)}) &&
    registerOp({"sigmoid", "y = 1 / (1 + exp(-x))", {"x"}, {}, {}, {"y"}, unary(sigmoid), examples(false)}) &&
    registerOp({"tanh", "y = tanh(x)", {"x"}, {}, {}, {"y"}, unary(tanh), examples(false)});

}  // namespace
}  // namespace smokesvd::fn

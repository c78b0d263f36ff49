#include "nets/functional/conv.h"

#include <string>

#include "nets/op_registry.h"
#include "runtime/error.h"

namespace smokesvd::fn {
namespace {

void requireRank(const char* op, const Var& x, int rank) {
  if (x->value.rank() != rank)
    throw Error(std::string(op) + ": input " + toString(x->value.shape()) + " must be " + std::to_string(rank) + "D");
}

// y = addend + conv(f(x), w) + b (f the leaky ReLU of params.inputSlope, none at 1; no addend: 0), or the
// transposed convolution; the backward of each is made of the other's kernels.
Var convolution(Tape& tape, const Var& x, const Var& w, const Var& bias, const ops::ConvParams& params,
                bool transposed, const Var& addend = nullptr) {
  const Shape yShape = transposed ? ops::convTransposeOutputShape(x->value.shape(), w->value.shape(), params)
                                  : ops::convOutputShape(x->value.shape(), w->value.shape(), params);
  Tensor y(tape.context(), yShape);
  const Tensor* b = bias ? &bias->value : nullptr;
  // A convolution whose weight learns keeps its padded input for the weight gradient.
  ops::PaddedInput padded;
  ops::PaddedInput* keep = w->requiresGrad && tape.gradEnabled() ? &padded : nullptr;
  if (transposed)
    ops::convTransposeForward(tape.stream(), x->value, w->value, b, params, y);
  else if (addend)
    ops::convForwardPlus(tape.stream(), x->value, w->value, b, addend->value, params, y, {}, keep);
  else
    ops::convForward(tape.stream(), x->value, w->value, b, params, y, {}, keep);
  Var out = tape.output(y, {x, w, bias, addend});
  if (!out->requiresGrad) return out;
  tape.record({out}, [x, w, bias, addend, out, params, transposed, padded](Tape& t) {
    const Tensor g = t.grad(out);
    if (addend && addend->requiresGrad) t.accumulate(addend, g);
    if (x->requiresGrad && transposed) {
      Tensor dx(t.context(), x->value.shape());
      ops::convTransposeBackwardInput(t.stream(), g, w->value, params, dx);
      t.accumulate(x, dx);
    } else if (x->requiresGrad) {
      t.accumulateWriting(x, [&](const Tensor* sofar, const Tensor& dx) {
        ops::convBackwardActivatedInput(t.stream(), g, w->value, x->value, params, dx, sofar);
      });
    }
    if (w->requiresGrad) {
      Tensor dw(t.context(), w->value.shape());
      if (transposed)
        ops::convTransposeBackwardWeight(t.stream(), x->value, g, params, dw);
      else
        ops::convBackwardWeight(t.stream(), x->value, g, params, dw, {}, &padded);
      t.accumulate(w, dw);
    }
    if (bias && bias->requiresGrad) {
      Tensor db(t.context(), bias->value.shape());
      ops::convBackwardBias(t.stream(), g, db);
      t.accumulate(bias, db);
    }
  });
  return out;
}

}  // namespace

Var conv2d(Tape& tape, const Var& x, const Var& w, const Var& bias, const ops::ConvParams& params,
           const Var& addend) {
  requireRank("conv2d", x, 4);
  return convolution(tape, x, w, bias, params, false, addend);
}

Var conv3d(Tape& tape, const Var& x, const Var& w, const Var& bias, const ops::ConvParams& params,
           const Var& addend) {
  requireRank("conv3d", x, 5);
  return convolution(tape, x, w, bias, params, false, addend);
}

Var convTranspose2d(Tape& tape, const Var& x, const Var& w, const Var& bias, const ops::ConvParams& params) {
  requireRank("convTranspose2d", x, 4);
  return convolution(tape, x, w, bias, params, true);
}

Var convTranspose3d(Tape& tape, const Var& x, const Var& w, const Var& bias, const ops::ConvParams& params) {
  requireRank("convTranspose3d", x, 5);
  return convolution(tape, x, w, bias, params, true);
}

namespace {

// Every convolution as the registry runs it: x, w, b and (a convolution only) the addend.
using ConvFunction = Var (*)(Tape&, const Var&, const Var&, const Var&, const ops::ConvParams&, const Var&);

Var convTranspose2dOp(Tape& t, const Var& x, const Var& w, const Var& b, const ops::ConvParams& p, const Var&) {
  return convTranspose2d(t, x, w, b, p);
}
Var convTranspose3dOp(Tape& t, const Var& x, const Var& w, const Var& b, const ops::ConvParams& p, const Var&) {
  return convTranspose3d(t, x, w, b, p);
}

OpSpec convSpec(std::string name, std::string summary, ConvFunction function, bool transposed) {
  std::vector<AttrSpec> attrs{{"stride", "1", "the same along every axis"},
                              {"padding", "0", "zero padding, the same along every axis"}};
  if (transposed)
    attrs.push_back({"output_padding", "0", "extra output rows at the high end, below the stride"});
  else
    attrs.push_back({"input_slope", "1", "x is read through leaky ReLU with this negative slope (1: as it is)"});
  std::vector<std::string> optional{"b"};
  if (!transposed) optional.push_back("addend");
  return {std::move(name), std::move(summary), {"x", "w"}, std::move(optional), std::move(attrs), {"y"},
          [function, transposed](Tape& t, const std::vector<Var>& in, const OpAttrs& a) {
            ops::ConvParams params;
            params.stride = static_cast<int>(a.integer("stride"));
            params.padding = static_cast<int>(a.integer("padding"));
            if (transposed)
              params.outputPadding = static_cast<int>(a.integer("output_padding"));
            else
              params.inputSlope = static_cast<float>(a.number("input_slope"));
            const Var addend = !transposed && in.size() > 3 ? in[3] : nullptr;
            return std::vector<Var>{function(t, in[0], in[1], in[2], params, addend)};
          }};
}

// x, w and (when bias) b of a convolution example; conv is linear in each, so the step can be large.
OpExample convExample(std::string name, Shape x, Shape w, int64_t outChannels, bool bias,
                      std::map<std::string, std::string> attrs) {
  OpExample example{.name = std::move(name),
                    .inputs = {{"x", draw::uniform(std::move(x))}, {"w", draw::uniform(std::move(w))}},
                    .attrs = std::move(attrs),
                    .gradient = {.step = 0.25}};
  if (bias) example.inputs.emplace("b", draw::uniform({outChannels}));
  return example;
}

// A convolution that reads x through leaky ReLU: x away from the kink at 0, steps that do not cross it.
// With an output shape: an addend of that shape too (a residual connection, as the bottleneck blocks add it).
OpExample activatedConvExample(std::string name, Shape x, Shape w, int64_t outChannels,
                               std::map<std::string, std::string> attrs, Shape addend = {}) {
  attrs.emplace("input_slope", "0.2");
  OpExample example{.name = std::move(name),
                    .inputs = {{"x", draw::awayFromZero(std::move(x))},
                               {"w", draw::uniform(std::move(w))},
                               {"b", draw::uniform({outChannels})}},
                    .attrs = std::move(attrs)};
  if (!addend.empty()) example.inputs.emplace("addend", draw::uniform(std::move(addend)));
  return example;
}

OpSpec withExamples(OpSpec spec, std::vector<OpExample> examples) {
  spec.examples = std::move(examples);
  return spec;
}

const bool registered =
    registerOp(withExamples(
        convSpec("conv2d", "y = addend + conv2d(f(x), w) + b; x [N,C,H,W], w [K,C,kH,kW], b [K], addend as y",
                 conv2d, false),
        {convExample("3x3, padding 1, bias", {2, 3, 7, 6}, {5, 3, 3, 3}, 5, true, {{"padding", "1"}}),
         convExample("2x3, stride 2, no bias", {1, 2, 9, 8}, {4, 2, 2, 3}, 4, false, {{"stride", "2"}}),
         convExample("1x1", {2, 5, 3, 4}, {3, 5, 1, 1}, 3, true, {}),
         activatedConvExample("1x1 through leaky ReLU, plus an addend", {2, 5, 3, 4}, {3, 5, 1, 1}, 3, {},
                              {2, 3, 3, 4}),
         activatedConvExample("3x3 through leaky ReLU, padding 1", {2, 3, 5, 6}, {4, 3, 3, 3}, 4,
                              {{"padding", "1"}})})) &&
    registerOp(withExamples(
        convSpec("conv3d", "y = addend + conv3d(f(x), w) + b; x [N,C,D,H,W], w [K,C,kD,kH,kW], b [K], addend as y",
                 conv3d, false),
        {convExample("3x3x3, stride 2, padding 1, bias", {1, 2, 5, 6, 7}, {3, 2, 3, 3, 3}, 3, true,
                     {{"stride", "2"}, {"padding", "1"}}),
         convExample("3x3x3, padding 1, 8 channels", {1, 3, 3, 4, 5}, {8, 3, 3, 3, 3}, 8, false, {{"padding", "1"}}),
         activatedConvExample("1x1x1 through leaky ReLU, plus an addend", {2, 6, 2, 3, 2}, {5, 6, 1, 1, 1}, 5, {},
                              {2, 5, 2, 3, 2}),
         activatedConvExample("3x3x3 through leaky ReLU, stride 2, padding 1, plus an addend", {1, 2, 5, 4, 5},
                              {3, 2, 3, 3, 3}, 3, {{"stride", "2"}, {"padding", "1"}}, {1, 3, 3, 2, 3})})) &&
    registerOp(withExamples(
        convSpec("conv_transpose2d", "y = conv_transpose2d(x, w) + b; x [N,C,H,W], w [C,K,kH,kW], b [K]",
                 convTranspose2dOp, true),
        {convExample("3x3, stride 2, padding 1, output padding 1", {1, 3, 4, 5}, {3, 2, 3, 3}, 2, true,
                     {{"stride", "2"}, {"padding", "1"}, {"output_padding", "1"}}),
         convExample("2x2, stride 2", {2, 2, 3, 3}, {2, 4, 2, 2}, 4, false, {{"stride", "2"}})})) &&
    registerOp(withExamples(
        convSpec("conv_transpose3d", "y = conv_transpose3d(x, w) + b; x [N,C,D,H,W], w [C,K,kD,kH,kW], b [K]",
                 convTranspose3dOp, true),
        {convExample("2x2x2, stride 2, bias", {1, 2, 2, 3, 3}, {2, 3, 2, 2, 2}, 3, true, {{"stride", "2"}}),
         convExample("3x3x3, padding 1", {1, 2, 3, 3, 4}, {2, 2, 3, 3, 3}, 2, false, {{"padding", "1"}})}));

}  // namespace
}  // namespace smokesvd::fn

#include "nets/functional/reduce_axes.h"

#include "nets/op_registry.h"
#include "nets/ops/broadcast.h"
#include "nets/ops/elementwise.h"
#include "nets/ops/reduce_axes.h"

namespace smokesvd::fn {
namespace {

Var reduce(Tape& tape, const Var& x, const std::vector<int>& requested, bool keepdims, bool average) {
  const Shape& shape = x->value.shape();
  const std::vector<int> axes =
      requested.empty() ? ops::allAxes(x->value.rank()) : ops::normalizeAxes(average ? "mean" : "sum", requested, shape);
  const float scale = average ? 1.0f / static_cast<float>(ops::reducedCount(shape, axes)) : 1.0f;
  Tensor y(tape.context(), ops::reducedShape(shape, axes, keepdims));
  ops::reduceAxes(tape.stream(), ops::ReduceMap::Identity, x->value, nullptr, axes, scale, y);
  Var out = tape.output(y, {x});
  if (out->requiresGrad) {
    tape.record({out}, [x, out, axes, scale](Tape& t) {
      const Shape kept = ops::reducedShape(x->value.shape(), axes, true);
      Tensor gx(t.context(), x->value.shape());
      ops::expand(t.stream(), t.grad(out).reshaped(kept), gx);
      if (scale != 1.0f) ops::scale(t.stream(), gx, scale, gx);
      t.accumulate(x, gx);
    });
  }
  return out;
}

std::vector<int> parseAxes(const OpAttrs& attrs) {
  if (attrs.text("axes") == "all") return {};
  std::vector<int> axes;
  for (int64_t axis : attrs.integers("axes")) axes.push_back(static_cast<int>(axis));
  return axes;
}

}  // namespace

Var sum(Tape& tape, const Var& x, std::vector<int> axes, bool keepdims) { return reduce(tape, x, axes, keepdims, false); }
Var mean(Tape& tape, const Var& x, std::vector<int> axes, bool keepdims) { return reduce(tape, x, axes, keepdims, true); }

namespace {

const std::vector<AttrSpec> kAttrs{{"axes", "all", "comma-separated axes (negative from the end) or all"},
                                   {"keepdims", "0", "1 keeps reduced axes with extent 1"}};

std::vector<OpExample> examples() {
  return {{.name = "channels", .inputs = {{"x", draw::uniform({2, 3, 5, 7})}}, .attrs = {{"axes", "1"}},
           .gradient = {.step = 0.25}},
          {.name = "batch and space, keepdims", .inputs = {{"x", draw::uniform({2, 3, 5, 7})}},
           .attrs = {{"axes", "0,2,3"}, {"keepdims", "1"}}, .gradient = {.step = 0.25}},
          {.name = "last axis, 4-aligned", .inputs = {{"x", draw::uniform({3, 8})}}, .attrs = {{"axes", "-1"}},
           .gradient = {.step = 0.25}},
          {.name = "everything", .inputs = {{"x", draw::uniform({3, 5, 7})}}, .gradient = {.step = 0.25}}};
}

const bool registered =
    registerOp({"sum", "y = sum of x over axes", {"x"}, {}, kAttrs, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{sum(t, in[0], parseAxes(attrs), attrs.integer("keepdims") != 0)};
                },
                examples()}) &&
    registerOp({"mean", "y = mean of x over axes", {"x"}, {}, kAttrs, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{mean(t, in[0], parseAxes(attrs), attrs.integer("keepdims") != 0)};
                },
                examples()});

}  // namespace
}  // namespace smokesvd::fn

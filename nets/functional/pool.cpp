#include "nets/functional/pool.h"

#include "nets/op_registry.h"
#include "nets/ops/pool.h"

namespace smokesvd::fn {
namespace {

Var pool(Tape& tape, const Var& x, ops::PoolKind kind) {
  Tensor y(tape.context(), ops::pooledShape(x->value.shape()));
  ops::poolForward(tape.stream(), kind, x->value, y);
  Var out = tape.output(y, {x});
  if (out->requiresGrad) {
    tape.record({out}, [x, out, kind](Tape& t) {
      Tensor gx(t.context(), x->value.shape());
      ops::poolBackward(t.stream(), kind, x->value, t.grad(out), gx);
      t.accumulate(x, gx);
    });
  }
  return out;
}

}  // namespace

Var maxPool(Tape& tape, const Var& x) { return pool(tape, x, ops::PoolKind::Max); }
Var avgPool(Tape& tape, const Var& x) { return pool(tape, x, ops::PoolKind::Average); }

namespace {

std::vector<Var> applyMax(Tape& t, const std::vector<Var>& in, const OpAttrs&) { return {maxPool(t, in[0])}; }
std::vector<Var> applyAverage(Tape& t, const std::vector<Var>& in, const OpAttrs&) { return {avgPool(t, in[0])}; }

// Odd extents (the ceil mode's partial windows) and 4-aligned ones, 2D and 3D. Max pooling gets
// distinct values (no ties) and a step below their spacing, so no window changes its maximum.
std::vector<OpExample> examples(bool max) {
  auto x = [max](Shape shape) { return max ? draw::distinct(std::move(shape)) : draw::uniform(std::move(shape)); };
  const GradientCheck gradient{.step = max ? 1e-3 : 0.25};
  return {{.name = "2D, odd extents", .inputs = {{"x", x({2, 3, 5, 7})}}, .gradient = gradient},
          {.name = "2D, 4-aligned rows", .inputs = {{"x", x({1, 2, 4, 8})}}, .gradient = gradient},
          {.name = "3D, odd extents", .inputs = {{"x", x({1, 2, 5, 4, 3})}}, .gradient = gradient}};
}

const bool registered =
    registerOp({"max_pool", "2D/3D max pooling, kernel 2, stride 2, ceil mode", {"x"}, {}, {}, {"y"}, applyMax,
                examples(true)}) &&
    registerOp({"avg_pool", "2D/3D average pooling, kernel 2, stride 2, ceil mode", {"x"}, {}, {}, {"y"},
                applyAverage, examples(false)});

}  // namespace
}  // namespace smokesvd::fn

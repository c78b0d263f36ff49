#include "nets/functional/concat.h"

#include <algorithm>

#include "nets/functional/broadcast.h"
#include "nets/op_registry.h"
#include "nets/ops/concat.h"

namespace smokesvd::fn {

Var concatChannels(Tape& tape, const std::vector<Var>& inputs) {
  std::vector<Tensor> values;
  std::vector<Shape> shapes;
  for (const Var& input : inputs) {
    values.push_back(input->value);
    shapes.push_back(input->value.shape());
  }
  Tensor y(tape.context(), ops::concatShape(shapes));
  ops::concatChannels(tape.stream(), values, y);
  Var out = tape.output(y, {});
  out->requiresGrad =
      tape.gradEnabled() && std::any_of(inputs.begin(), inputs.end(), [](const Var& v) { return v->requiresGrad; });
  if (out->requiresGrad) {
    tape.record({out}, [inputs, out](Tape& t) {
      const Tensor g = t.grad(out);
      int64_t offset = 0;
      for (const Var& input : inputs) {
        const int64_t channels = input->value.size(1);
        if (input->requiresGrad) {
          Tensor gi(t.context(), input->value.shape());
          ops::sliceChannels(t.stream(), g, offset, offset + channels, gi);
          t.accumulate(input, gi);
        }
        offset += channels;
      }
    });
  }
  return out;
}

Var sliceChannels(Tape& tape, const Var& x, int64_t begin, int64_t end) {
  Shape shape = x->value.shape();
  if (shape.size() >= 2) shape[1] = std::max<int64_t>(end - begin, 0);
  Tensor y(tape.context(), shape);
  ops::sliceChannels(tape.stream(), x->value, begin, end, y);
  Var out = tape.output(y, {x});
  if (out->requiresGrad) {
    tape.record({out}, [x, out, begin](Tape& t) {
      Tensor gx(t.context(), x->value.shape());
      t.stream().fillZero(gx);
      const Tensor g = t.grad(out);
      ops::copyChannels(t.stream(), g, 0, gx, begin, g.size(1));
      t.accumulate(x, gx);
    });
  }
  return out;
}

Var sliceBatch(Tape& tape, const Var& x, int64_t begin, int64_t end) {
  const Shape& shape = x->value.shape();
  const int64_t items = shape.at(0);
  Shape sliced = shape;
  sliced[0] = std::max<int64_t>(end - begin, 0);
  const Var asChannels = reshape(tape, x, {1, items, x->value.numel() / std::max<int64_t>(items, 1)});
  return reshape(tape, sliceChannels(tape, asChannels, begin, end), sliced);
}

namespace {

const bool registered =
    registerOp({"concat_channels", "y = cat(a, b, ...) along axis 1", {"a", "b"}, {"c", "d", "e", "f"}, {}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) {
                  std::vector<Var> present;
                  std::copy_if(in.begin(), in.end(), std::back_inserter(present), [](const Var& v) { return v != nullptr; });
                  return std::vector<Var>{concatChannels(t, present)};
                },
                {{.name = "two inputs, odd planes",
                  .inputs = {{"a", draw::uniform({2, 3, 5})}, {"b", draw::uniform({2, 1, 5})}},
                  .gradient = {.step = 0.25}},
                 {.name = "four inputs, 4-aligned planes",
                  .inputs = {{"a", draw::uniform({2, 1, 2, 4})},
                             {"b", draw::uniform({2, 2, 2, 4})},
                             {"c", draw::uniform({2, 1, 2, 4})},
                             {"d", draw::uniform({2, 3, 2, 4})}},
                  .gradient = {.step = 0.25}}}}) &&
    registerOp({"slice_channels", "y = x[:, begin:end]", {"x"}, {},
                {{"begin", "", "first channel"}, {"end", "", "one past the last channel"}}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{sliceChannels(t, in[0], attrs.integer("begin"), attrs.integer("end"))};
                },
                {{.name = "middle channels", .inputs = {{"x", draw::uniform({2, 5, 3, 3})}},
                  .attrs = {{"begin", "1"}, {"end", "4"}}, .gradient = {.step = 0.25}},
                 {.name = "4-aligned planes", .inputs = {{"x", draw::uniform({1, 4, 2, 2})}},
                  .attrs = {{"begin", "2"}, {"end", "4"}}, .gradient = {.step = 0.25}}}}) &&
    registerOp({"slice_batch", "y = x[begin:end] along the first axis", {"x"}, {},
                {{"begin", "", "first item"}, {"end", "", "one past the last item"}}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{sliceBatch(t, in[0], attrs.integer("begin"), attrs.integer("end"))};
                },
                {{.name = "views of an image stack", .inputs = {{"x", draw::uniform({6, 1, 3, 5})}},
                  .attrs = {{"begin", "2"}, {"end", "5"}}, .gradient = {.step = 0.25}}}});

}  // namespace
}  // namespace smokesvd::fn

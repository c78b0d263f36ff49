#include "nets/functional/conv_of_parts.h"

#include <algorithm>
#include <string>

#include "nets/op_registry.h"
#include "nets/ops/concat.h"
#include "nets/ops/elementwise.h"
#include "runtime/error.h"

namespace smokesvd::fn {
namespace {

// w viewed as [1, K, rest]: the channel ops then act on its output channels.
Tensor byOutputChannel(const Tensor& w) { return w.reshaped({1, w.size(0), w.numel() / w.size(0)}); }

// w[outBegin:outEnd, inBegin:inEnd] as a tensor of its own.
Tensor weightBlock(Stream& stream, const Tensor& w, int64_t outBegin, int64_t outEnd, int64_t inBegin, int64_t inEnd) {
  Shape rowsShape = w.shape();
  rowsShape[0] = outEnd - outBegin;
  Tensor rows(stream.context(), rowsShape);
  ops::sliceChannels(stream, byOutputChannel(w), outBegin, outEnd, byOutputChannel(rows));
  Shape blockShape = rowsShape;
  blockShape[1] = inEnd - inBegin;
  Tensor block(stream.context(), blockShape);
  ops::sliceChannels(stream, rows, inBegin, inEnd, block);
  return block;
}

void requireParts(const std::vector<Var>& parts, const Var& w, const Var& bias, int64_t outBegin, int64_t outEnd) {
  if (parts.empty()) throw Error("conv_of_parts: no parts");
  if (!w) throw Error("conv_of_parts: no weight");
  const int rank = w->value.rank();
  int64_t channels = 0;
  for (const Var& part : parts) {
    if (!part || part->value.rank() != rank)
      throw Error("conv_of_parts: every part must have the weight's rank " + std::to_string(rank) + ", got " +
                  (part ? toString(part->value.shape()) : std::string("none")));
    channels += part->value.size(1);
  }
  if (channels != w->value.size(1))
    throw Error("conv_of_parts: the parts hold " + std::to_string(channels) + " channels, the weight " +
                toString(w->value.shape()) + " expects " + std::to_string(w->value.size(1)));
  if (outBegin < 0 || outEnd <= outBegin || outEnd > w->value.size(0))
    throw Error("conv_of_parts: output channels [" + std::to_string(outBegin) + ", " + std::to_string(outEnd) +
                ") outside the weight's " + std::to_string(w->value.size(0)));
  if (bias && bias->value.shape() != Shape{w->value.size(0)})
    throw Error("conv_of_parts: bias " + toString(bias->value.shape()) + ", expected [" +
                std::to_string(w->value.size(0)) + "]");
}

}  // namespace

Var convOfParts(Tape& tape, const std::vector<Var>& parts, const Var& w, const Var& bias, const ops::ConvParams& params,
                int64_t outBegin, int64_t outEnd) {
  requireParts(parts, w, bias, outBegin, outEnd);
  Stream& stream = tape.stream();
  const int64_t groupChannels = outEnd - outBegin;
  std::vector<Tensor> blocks;
  int64_t offset = 0;
  for (const Var& part : parts) {
    blocks.push_back(weightBlock(stream, w->value, outBegin, outEnd, offset, offset + part->value.size(1)));
    offset += part->value.size(1);
  }
  Tensor groupBias;
  if (bias) {
    groupBias = Tensor(tape.context(), {groupChannels});
    ops::sliceChannels(stream, bias->value.reshaped({1, bias->value.size(0)}), outBegin, outEnd,
                       groupBias.reshaped({1, groupChannels}));
  }

  const Shape yShape = ops::convOutputShape(parts[0]->value.shape(), blocks[0].shape(), params);
  Tensor y(tape.context(), yShape);
  ops::convForward(stream, parts[0]->value, blocks[0], bias ? &groupBias : nullptr, params, y);
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const Tensor term(tape.context(), ops::convOutputShape(parts[i]->value.shape(), blocks[i].shape(), params));
    if (term.shape() != yShape)
      throw Error("conv_of_parts: part " + std::to_string(i) + " " + toString(parts[i]->value.shape()) +
                  " does not match part 0 " + toString(parts[0]->value.shape()));
    ops::convForward(stream, parts[i]->value, blocks[i], nullptr, params, term);
    ops::axpy(stream, 1.0f, term, y);
  }

  Var out = tape.output(y, {});
  out->requiresGrad = tape.gradEnabled() && (w->requiresGrad || (bias && bias->requiresGrad) ||
                                             std::any_of(parts.begin(), parts.end(), [](const Var& p) { return p->requiresGrad; }));
  if (!out->requiresGrad) return out;
  tape.record({out}, [parts, w, bias, out, params, outBegin, groupChannels, blocks](Tape& t) {
    Stream& s = t.stream();
    const Tensor g = t.grad(out);
    for (std::size_t i = 0; i < parts.size(); ++i)
      if (parts[i]->requiresGrad) {
        Tensor dx(t.context(), parts[i]->value.shape());
        ops::convBackwardInput(s, g, blocks[i], params, dx);
        t.accumulate(parts[i], dx);
      }
    if (w->requiresGrad) {
      Shape rowsShape = w->value.shape();
      rowsShape[0] = groupChannels;
      Tensor rows(t.context(), rowsShape);
      int64_t inBegin = 0;
      for (std::size_t i = 0; i < parts.size(); ++i) {
        Tensor block(t.context(), blocks[i].shape());
        ops::convBackwardWeight(s, parts[i]->value, g, params, block);
        ops::copyChannels(s, block, 0, rows, inBegin, block.size(1));
        inBegin += block.size(1);
      }
      Tensor dw(t.context(), w->value.shape());
      s.fillZero(dw);
      ops::copyChannels(s, byOutputChannel(rows), 0, byOutputChannel(dw), outBegin, groupChannels);
      t.accumulate(w, dw);
    }
    if (bias && bias->requiresGrad) {
      Tensor groupGrad(t.context(), {groupChannels});
      ops::convBackwardBias(s, g, groupGrad);
      Tensor db(t.context(), bias->value.shape());
      s.fillZero(db);
      ops::copyChannels(s, groupGrad.reshaped({1, groupChannels}), 0, db.reshaped({1, bias->value.size(0)}), outBegin,
                        groupChannels);
      t.accumulate(bias, db);
    }
  });
  return out;
}

namespace {

const bool registered = registerOp(
    {"conv_of_parts",
     "y = conv(cat(a, b, ...), w[out_begin:out_end]) + bias[out_begin:out_end]; parts N,C_i,..., w [K, sum C_i, k...]",
     {"a", "b", "w"},
     {"c", "bias"},
     {{"stride", "1", "the same along every axis"},
      {"padding", "0", "zero padding, the same along every axis"},
      {"out_begin", "", "first output channel"},
      {"out_end", "", "one past the last output channel"}},
     {"y"},
     [](Tape& t, const std::vector<Var>& in, const OpAttrs& a) {
       std::vector<Var> parts{in[0], in[1]};
       if (in[3]) parts.push_back(in[3]);
       ops::ConvParams params;
       params.stride = static_cast<int>(a.integer("stride"));
       params.padding = static_cast<int>(a.integer("padding"));
       return std::vector<Var>{convOfParts(t, parts, in[2], in[4], params, a.integer("out_begin"), a.integer("out_end"))};
     },
     // conv is linear in each input, so the difference step can be large.
     {{.name = "3D 3x3x3, three parts, padding 1, bias, middle output group",
       .inputs = {{"a", draw::uniform({1, 2, 3, 4, 5})},
                  {"b", draw::uniform({1, 3, 3, 4, 5})},
                  {"c", draw::uniform({1, 1, 3, 4, 5})},
                  {"w", draw::uniform({7, 6, 3, 3, 3})},
                  {"bias", draw::uniform({7})}},
       .attrs = {{"padding", "1"}, {"out_begin", "2"}, {"out_end", "5"}},
       .gradient = {.step = 0.25}},
      {.name = "2D 1x1, two parts, stride 2, no bias, every output",
       .inputs = {{"a", draw::uniform({2, 3, 5, 7})}, {"b", draw::uniform({2, 2, 5, 7})}, {"w", draw::uniform({4, 5, 1, 1})}},
       .attrs = {{"stride", "2"}, {"out_begin", "0"}, {"out_end", "4"}},
       .gradient = {.step = 0.25}}}});

}  // namespace
}  // namespace smokesvd::fn

#include "nets/functional/losses.h"

#include "nets/op_registry.h"
#include "nets/ops/elementwise.h"
#include "nets/ops/losses.h"

namespace smokesvd::fn {
namespace {

Tensor scalar(const Tape& tape) { return Tensor(tape.context(), {1}); }
Tensor like(const Tape& tape, const Var& v) { return Tensor(tape.context(), v->value.shape()); }

// For losses of a - b: gives ga to a and -ga to b. `gradientOfA` writes ga.
template <typename Backward>
void recordDifferenceLoss(Tape& tape, const Var& a, const Var& b, const Var& out, Backward gradientOfA) {
  if (!out->requiresGrad) return;
  tape.record({out}, [a, b, out, gradientOfA](Tape& t) {
    Tensor ga = like(t, a);
    gradientOfA(t, t.grad(out), ga);
    t.accumulate(a, ga);
    if (b->requiresGrad) {
      Tensor gb = like(t, b);
      ops::scale(t.stream(), ga, -1.0f, gb);
      t.accumulate(b, gb);
    }
  });
}

}  // namespace

Var mseLoss(Tape& tape, const Var& a, const Var& b) {
  Tensor loss = scalar(tape);
  ops::mseLoss(tape.stream(), a->value, b->value, loss);
  Var out = tape.output(loss, {a, b});
  recordDifferenceLoss(tape, a, b, out, [a, b](Tape& t, const Tensor& g, const Tensor& ga) {
    ops::mseLossBackward(t.stream(), g, a->value, b->value, ga);
  });
  return out;
}

Var l1Loss(Tape& tape, const Var& a, const Var& b) {
  Tensor loss = scalar(tape);
  ops::l1Loss(tape.stream(), a->value, b->value, loss);
  Var out = tape.output(loss, {a, b});
  recordDifferenceLoss(tape, a, b, out, [a, b](Tape& t, const Tensor& g, const Tensor& ga) {
    ops::l1LossBackward(t.stream(), g, a->value, b->value, ga);
  });
  return out;
}

Var rowSumLoss(Tape& tape, const Var& a, const Var& b) {
  const int64_t width = a->value.rank() > 0 ? a->value.size(-1) : 1;
  Tensor rows(tape.context(), {a->value.numel() / std::max<int64_t>(width, 1)});
  Tensor loss = scalar(tape);
  ops::rowSumLoss(tape.stream(), a->value, b->value, rows, loss);
  Var out = tape.output(loss, {a, b});
  recordDifferenceLoss(tape, a, b, out, [rows](Tape& t, const Tensor& g, const Tensor& ga) {
    ops::rowSumLossBackward(t.stream(), g, rows, ga);
  });
  return out;
}

Var psnr(Tape& tape, const Var& a, const Var& b, float dataRange) {
  const ops::PsnrParams params{dataRange};
  Tensor mse(tape.context(), {a->value.rank() > 0 ? a->value.size(0) : 1});
  ops::sampleMse(tape.stream(), a->value, b->value, mse);
  Tensor result = scalar(tape);
  ops::psnr(tape.stream(), mse, params, result);
  Var out = tape.output(result, {a, b});
  recordDifferenceLoss(tape, a, b, out, [a, b, mse, params](Tape& t, const Tensor& g, const Tensor& ga) {
    ops::psnrBackward(t.stream(), g, mse, a->value, b->value, params, ga);
  });
  return out;
}

Var psnrGapLoss(Tape& tape, const Var& a, const Var& b, const Var& reference, float dataRange) {
  const ops::PsnrParams params{dataRange};
  const Shape samples{a->value.rank() > 0 ? a->value.size(0) : 1};
  Tensor mseA(tape.context(), samples), mseB(tape.context(), samples);
  ops::sampleMse(tape.stream(), a->value, reference->value, mseA);
  ops::sampleMse(tape.stream(), b->value, reference->value, mseB);
  Tensor gap = scalar(tape);
  ops::psnrGap(tape.stream(), mseA, mseB, params, gap);
  Var out = tape.output(gap, {a, b, reference});
  if (out->requiresGrad) {
    tape.record({out}, [a, b, reference, out, mseA, mseB, params](Tape& t) {
      const Tensor g = t.grad(out);
      Tensor ga = like(t, a), gb = like(t, b);
      if (a->requiresGrad || reference->requiresGrad)
        ops::psnrGapBackward(t.stream(), g, mseA, mseB, a->value, reference->value, params, ga);
      if (b->requiresGrad || reference->requiresGrad)
        ops::psnrGapBackward(t.stream(), g, mseB, mseA, b->value, reference->value, params, gb);
      if (reference->requiresGrad) {  // the gap depends on a - reference and b - reference
        Tensor gr = like(t, reference);
        ops::axpby(t.stream(), -1.0f, ga, -1.0f, gb, gr);
        t.accumulate(reference, gr);
      }
      t.accumulate(a, ga);
      t.accumulate(b, gb);
    });
  }
  return out;
}

Var meanResidualSquared(Tape& tape, const Var& residual) {
  Tensor mean = scalar(tape), loss = scalar(tape);
  ops::meanResidualSquared(tape.stream(), residual->value, mean, loss);
  Var out = tape.output(loss, {residual});
  if (out->requiresGrad) {
    tape.record({out}, [residual, out, mean](Tape& t) {
      Tensor gx = like(t, residual);
      ops::meanResidualSquaredBackward(t.stream(), t.grad(out), mean, gx);
      t.accumulate(residual, gx);
    });
  }
  return out;
}

namespace {

using Inputs = const std::vector<Var>&;
const AttrSpec kRange{"data_range", "1", "peak value of the images (their range)"};

// Two images of odd and of 4-aligned shape.
std::vector<OpExample> pairExamples() {
  return {{.name = "odd shape", .inputs = {{"a", draw::uniform({2, 3, 5, 7})}, {"b", draw::uniform({2, 3, 5, 7})}}},
          {.name = "4-aligned shape", .inputs = {{"a", draw::uniform({2, 1, 3, 8})}, {"b", draw::uniform({2, 1, 3, 8})}}}};
}

const bool registered =
    registerOp({"mse_loss", "loss = mean (a - b)^2", {"a", "b"}, {}, {}, {"loss"},
                [](Tape& t, Inputs in, const OpAttrs&) { return std::vector<Var>{mseLoss(t, in[0], in[1])}; },
                pairExamples()}) &&
    registerOp({"l1_loss", "loss = mean |a - b|", {"a", "b"}, {}, {}, {"loss"},
                [](Tape& t, Inputs in, const OpAttrs&) { return std::vector<Var>{l1Loss(t, in[0], in[1])}; },
                // a and b on interleaved lattices: |a - b| stays away from its kink at 0
                {{.name = "odd shape",
                  .inputs = {{"a", draw::lattice({2, 3, 5, 7}, -1, 1, 0.2f, 0)},
                             {"b", draw::lattice({2, 3, 5, 7}, -1, 1, 0.2f, 0.5f)}}},
                 {.name = "4-aligned shape",
                  .inputs = {{"a", draw::lattice({2, 8}, -1, 1, 0.2f, 0)}, {"b", draw::lattice({2, 8}, -1, 1, 0.2f, 0.5f)}}}}}) &&
    registerOp({"row_sum_loss", "loss = mean over rows of (sum_w a - sum_w b)^2 (L_sp)", {"a", "b"}, {}, {}, {"loss"},
                [](Tape& t, Inputs in, const OpAttrs&) { return std::vector<Var>{rowSumLoss(t, in[0], in[1])}; },
                pairExamples()}) &&
    registerOp({"psnr", "loss = mean over samples of PSNR(a, b)", {"a", "b"}, {}, {kRange}, {"loss"},
                [](Tape& t, Inputs in, const OpAttrs& attrs) {
                  return std::vector<Var>{psnr(t, in[0], in[1], static_cast<float>(attrs.number("data_range")))};
                },
                {{.name = "images in [0, 1]",
                  .inputs = {{"a", draw::uniform({2, 1, 6, 5}, 0, 1)}, {"b", draw::uniform({2, 1, 6, 5}, 0, 1)}}},
                 {.name = "range 4, 4-aligned rows",
                  .inputs = {{"a", draw::uniform({3, 2, 2, 4}, 0, 4)}, {"b", draw::uniform({3, 2, 2, 4}, 0, 4)}},
                  .attrs = {{"data_range", "4"}}}}}) &&
    registerOp({"psnr_gap_loss", "loss = mean over samples of (PSNR(a, ref) - PSNR(b, ref))^2",
                {"a", "b", "reference"}, {}, {kRange}, {"loss"},
                [](Tape& t, Inputs in, const OpAttrs& attrs) {
                  return std::vector<Var>{
                      psnrGapLoss(t, in[0], in[1], in[2], static_cast<float>(attrs.number("data_range")))};
                },
                {{.name = "images in [0, 1]",
                  .inputs = {{"a", draw::uniform({2, 1, 5, 6}, 0, 1)},
                             {"b", draw::uniform({2, 1, 5, 6}, 0, 1)},
                             {"reference", draw::uniform({2, 1, 5, 6}, 0, 1)}},
                  .gradient = {.step = 1e-3}}}}) &&
    registerOp({"mean_residual_squared", "loss = mean(x)^2", {"x"}, {}, {}, {"loss"},
                [](Tape& t, Inputs in, const OpAttrs&) { return std::vector<Var>{meanResidualSquared(t, in[0])}; },
                {{.name = "odd shape", .inputs = {{"x", draw::uniform({3, 5, 7})}}},
                 {.name = "4-aligned shape", .inputs = {{"x", draw::uniform({2, 4, 4})}}}}});

}  // namespace
}  // namespace smokesvd::fn

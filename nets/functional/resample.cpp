#include "nets/functional/resample.h"

#include "nets/op_registry.h"
#include "runtime/error.h"

namespace smokesvd::fn {
namespace {

Var resample(Tape& tape, const Var& x, const ops::Resample& resample) {
  Tensor y(tape.context(), ops::resampledShape(x->value.shape(), resample));
  ops::resampleForward(tape.stream(), resample, x->value, y);
  Var out = tape.output(y, {x});
  if (out->requiresGrad) {
    tape.record({out}, [x, out, resample](Tape& t) {
      Tensor gx(t.context(), x->value.shape());
      ops::resampleBackward(t.stream(), resample, t.grad(out), gx);
      t.accumulate(x, gx);
    });
  }
  return out;
}

}  // namespace

Var upsample(Tape& tape, const Var& x, int factor, ResampleMode mode) {
  return resample(tape, x, {mode, false, factor});
}

Var downsample(Tape& tape, const Var& x, int factor, ResampleMode mode) {
  return resample(tape, x, {mode, true, factor});
}

namespace {

ResampleMode modeAttr(const std::string& op, const OpAttrs& attrs) {
  const std::string mode = attrs.text("mode");
  if (mode == "nearest") return ResampleMode::Nearest;
  if (mode == "linear" || mode == "bilinear" || mode == "trilinear") return ResampleMode::Linear;
  throw Error("op " + op + ": attribute mode='" + mode + "' is not nearest, linear, bilinear or trilinear");
}

int factorAttr(const OpAttrs& attrs) { return static_cast<int>(attrs.integer("factor")); }

const std::vector<AttrSpec> kAttrs{{"factor", "2", "integer scale factor >= 1"},
                                   {"mode", "linear", "nearest or linear (bilinear in 2D, trilinear in 3D)"}};

OpExample example(std::string name, Shape shape, std::string mode, int factor) {
  return {.name = std::move(name),
          .inputs = {{"x", draw::uniform(std::move(shape))}},
          .attrs = {{"mode", std::move(mode)}, {"factor", std::to_string(factor)}},
          .gradient = {.step = 0.25}};
}

const bool registered =
    registerOp({"upsample", "F.interpolate(x, scale_factor=factor, mode), align_corners=False", {"x"}, {}, kAttrs,
                {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{upsample(t, in[0], factorAttr(attrs), modeAttr("upsample", attrs))};
                },
                {example("2D linear, odd width", {1, 2, 5, 7}, "linear", 2),
                 example("2D nearest, factor 3", {2, 1, 3, 5}, "nearest", 3),
                 example("2D linear, 4-aligned width", {2, 1, 3, 8}, "linear", 2),
                 example("3D linear, odd width", {1, 2, 3, 4, 5}, "trilinear", 2),
                 example("3D nearest, 4-aligned width", {1, 1, 2, 3, 4}, "nearest", 2),
                 example("3D linear, 4-aligned width", {1, 2, 3, 2, 4}, "linear", 2)}}) &&
    registerOp({"downsample", "F.interpolate(x, scale_factor=1/factor, mode), align_corners=False", {"x"}, {}, kAttrs,
                {"y"}, [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{downsample(t, in[0], factorAttr(attrs), modeAttr("downsample", attrs))};
                },
                {example("2D linear, odd extents", {1, 2, 9, 10}, "bilinear", 2),
                 example("2D nearest, factor 3", {2, 1, 7, 9}, "nearest", 3),
                 example("2D linear, 4-aligned width", {1, 2, 4, 16}, "linear", 2),
                 example("3D linear", {1, 2, 6, 5, 8}, "linear", 2),
                 example("3D nearest", {1, 1, 4, 6, 7}, "nearest", 2)}});

}  // namespace
}  // namespace smokesvd::fn

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

const bool registered =
    registerOp({"upsample", "F.interpolate(x, scale_factor=factor, mode), align_corners=False", {"x"}, {}, kAttrs,
                {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{upsample(t, in[0], factorAttr(attrs), modeAttr("upsample", attrs))};
                }}) &&
    registerOp({"downsample", "F.interpolate(x, scale_factor=1/factor, mode), align_corners=False", {"x"}, {}, kAttrs,
                {"y"}, [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{downsample(t, in[0], factorAttr(attrs), modeAttr("downsample", attrs))};
                }});

}  // namespace
}  // namespace smokesvd::fn

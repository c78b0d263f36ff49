#include "nets/ops/losses.h"

#include "nets/ops/broadcast.h"
#include "nets/ops/elementwise.h"
#include "nets/ops/reduce_axes.h"
#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{64, 1, 1};

// shaders/nn/loss_backward.comp: grad = scale * g * c[i / segment] * F(a, b)
enum class Form { Difference = 0, Sign = 1, Coefficient = 2 };
// shaders/nn/loss_psnr.comp
enum class PsnrMode { Mean = 0, Gap = 1, MeanCoefficients = 2, GapCoefficients = 3 };

// a and b are read by the Difference and Sign forms only.
void lossGradient(Stream& stream, Form form, const Tensor& g, const Tensor* coefficients, int64_t segment, float scale,
                  const Tensor* a, const Tensor* b, const Tensor& grad) {
  if (g.numel() != 1) throw Error("loss backward: the upstream gradient must be one element, got " + toString(g.shape()));
  if (form != Form::Coefficient) requireSameShape("loss backward", {a, b, &grad});
  struct {
    uint32_t n, segment;
    FastDivisor bySegment;
    float scale;
  } push{static_cast<uint32_t>(grad.numel()), static_cast<uint32_t>(segment),
         fastDivisor(static_cast<uint32_t>(segment)), scale};
  const Kernel& kernel = stream.kernel("nn/loss_backward", kWorkgroup,
                                       {static_cast<int32_t>(form), coefficients ? 1 : 0});
  stream.dispatchFlat(kernel, {g, coefficients ? *coefficients : g, a ? asVec4(*a) : Arg(g), b ? asVec4(*b) : Arg(g), grad},
                      push, (static_cast<uint64_t>(grad.numel()) + 3) / 4);
}

void requireScalar(const char* op, const Tensor& t) {
  if (t.numel() != 1) throw Error(std::string(op) + ": the result must be one element, got " + toString(t.shape()));
}

void requireInputs(const char* op, const Tensor& a, const Tensor& b) {
  requireSameShape(op, {&a, &b});
  if (a.numel() == 0) throw Error(std::string(op) + ": the inputs " + toString(a.shape()) + " are empty");
}

void reduceAll(Stream& stream, ReduceMap map, const Tensor& a, const Tensor* b, float scale, const Tensor& y) {
  const std::vector<int> axes = allAxes(a.rank());
  reduceAxes(stream, map, a, b, axes, scale, y);
}

float inverse(int64_t n) { return 1.0f / static_cast<float>(n); }

int64_t samples(const Tensor& mse) { return mse.numel(); }

void psnrKernel(Stream& stream, PsnrMode mode, const Tensor& x, const Tensor& z, float perSample,
                const PsnrParams& params, const Tensor& y) {
  struct { uint32_t N; float L, range, eps; } push{static_cast<uint32_t>(samples(x)), perSample, params.dataRange,
                                                   params.eps};
  const Kernel& kernel = stream.kernel("nn/loss_psnr", kWorkgroup, {static_cast<int32_t>(mode)});
  stream.dispatchFlat(kernel, {x, z, y}, push, mode == PsnrMode::Mean || mode == PsnrMode::Gap ? 1 : samples(x));
}

float elementsPerSample(const Tensor& image, const Tensor& mse) {
  if (image.rank() < 1 || image.size(0) != mse.numel())
    throw Error("psnr: " + std::to_string(mse.numel()) + " per-sample errors for images " + toString(image.shape()));
  return static_cast<float>(image.numel() / image.size(0));
}

}  // namespace

void mseLoss(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& loss) {
  requireInputs("mse loss", a, b);
  requireScalar("mse loss", loss);
  reduceAll(stream, ReduceMap::SquaredDifference, a, &b, inverse(a.numel()), loss);
}

void mseLossBackward(Stream& stream, const Tensor& g, const Tensor& a, const Tensor& b, const Tensor& ga) {
  lossGradient(stream, Form::Difference, g, nullptr, 1, 2.0f * inverse(a.numel()), &a, &b, ga);
}

void l1Loss(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& loss) {
  requireInputs("l1 loss", a, b);
  requireScalar("l1 loss", loss);
  reduceAll(stream, ReduceMap::AbsoluteDifference, a, &b, inverse(a.numel()), loss);
}

void l1LossBackward(Stream& stream, const Tensor& g, const Tensor& a, const Tensor& b, const Tensor& ga) {
  lossGradient(stream, Form::Sign, g, nullptr, 1, inverse(a.numel()), &a, &b, ga);
}

void rowSumLoss(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& rows, const Tensor& loss) {
  requireInputs("row-sum loss", a, b);
  requireScalar("row-sum loss", loss);
  if (a.rank() < 2) throw Error("row-sum loss: the images " + toString(a.shape()) + " need rows and columns");
  const int lastAxis[] = {a.rank() - 1};
  reduceAxes(stream, ReduceMap::Difference, a, &b, lastAxis, 1.0f, rows);
  reduceAll(stream, ReduceMap::Square, rows, nullptr, inverse(rows.numel()), loss);
}

void rowSumLossBackward(Stream& stream, const Tensor& g, const Tensor& rows, const Tensor& ga) {
  if (ga.rank() < 2 || ga.numel() != rows.numel() * ga.size(-1))
    throw Error("row-sum loss backward: " + std::to_string(rows.numel()) + " row sums for images " +
                toString(ga.shape()));
  lossGradient(stream, Form::Coefficient, g, &rows, ga.size(-1), 2.0f * inverse(rows.numel()), nullptr, nullptr, ga);
}

void sampleMse(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& mse) {
  requireInputs("psnr", a, b);
  if (a.rank() < 1 || mse.numel() != a.size(0))
    throw Error("psnr: per-sample errors " + toString(mse.shape()) + " for images " + toString(a.shape()));
  std::vector<int> axes = allAxes(a.rank());
  axes.erase(axes.begin());
  reduceAxes(stream, ReduceMap::SquaredDifference, a, &b, axes, 1.0f / elementsPerSample(a, mse), mse);
}

void psnr(Stream& stream, const Tensor& mse, const PsnrParams& params, const Tensor& result) {
  requireScalar("psnr", result);
  psnrKernel(stream, PsnrMode::Mean, mse, mse, 1.0f, params, result);
}

void psnrBackward(Stream& stream, const Tensor& g, const Tensor& mse, const Tensor& a, const Tensor& b,
                  const PsnrParams& params, const Tensor& ga) {
  const float perSample = elementsPerSample(a, mse);
  Tensor coefficients(stream.context(), {samples(mse)});
  psnrKernel(stream, PsnrMode::MeanCoefficients, mse, mse, perSample, params, coefficients);
  lossGradient(stream, Form::Difference, g, &coefficients, static_cast<int64_t>(perSample), 1.0f, &a, &b, ga);
}

void psnrGap(Stream& stream, const Tensor& mseA, const Tensor& mseB, const PsnrParams& params, const Tensor& gap) {
  requireScalar("psnr gap", gap);
  requireSameShape("psnr gap", {&mseA, &mseB});
  psnrKernel(stream, PsnrMode::Gap, mseA, mseB, 1.0f, params, gap);
}

void psnrGapBackward(Stream& stream, const Tensor& g, const Tensor& mseX, const Tensor& mseOther, const Tensor& x,
                     const Tensor& reference, const PsnrParams& params, const Tensor& gx) {
  const float perSample = elementsPerSample(x, mseX);
  Tensor coefficients(stream.context(), {samples(mseX)});
  psnrKernel(stream, PsnrMode::GapCoefficients, mseX, mseOther, perSample, params, coefficients);
  lossGradient(stream, Form::Difference, g, &coefficients, static_cast<int64_t>(perSample), 1.0f, &x, &reference, gx);
}

void meanResidualSquared(Stream& stream, const Tensor& x, const Tensor& mean, const Tensor& loss) {
  if (x.numel() == 0) throw Error("mean-residual loss: the input " + toString(x.shape()) + " is empty");
  requireScalar("mean-residual loss", mean);
  requireScalar("mean-residual loss", loss);
  reduceAll(stream, ReduceMap::Identity, x, nullptr, inverse(x.numel()), mean);
  reduceAll(stream, ReduceMap::Square, mean, nullptr, 1.0f, loss);
}

void meanResidualSquaredBackward(Stream& stream, const Tensor& g, const Tensor& mean, const Tensor& gx) {
  lossGradient(stream, Form::Coefficient, g, &mean, gx.numel(), 2.0f * inverse(gx.numel()), nullptr, nullptr, gx);
}

}  // namespace smokesvd::ops

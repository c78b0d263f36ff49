#include "pipeline/eval/volume_metrics.h"

#include <cmath>
#include <string>

#include "nets/ops/reduce_axes.h"
#include "pipeline/physics/differential.h"
#include "runtime/error.h"
#include "runtime/stream.h"

namespace smokesvd::eval {
namespace {

// scale * sum over every element of map(a, b), one value downloaded.
double reduced(Context& context, ops::ReduceMap map, const Tensor& a, const Tensor* b, double scale) {
  const Tensor out(context, {1});
  Stream stream(context);
  ops::reduceAxes(stream, map, a, b, ops::allAxes(a.rank()), static_cast<float>(scale), out);
  stream.submit();
  return out.download()[0];
}

void requireVelocity(const Tensor& velocity, const char* what) {
  if (velocity.rank() != 4 || velocity.size(0) != 3)
    throw Error(std::string("volume metrics: ") + what + " must be a velocity [3, D, H, W], got " + toString(velocity.shape()));
}

}  // namespace

double densityRmse(Context& context, const Tensor& density, const Tensor& reference) {
  if (density.shape() != reference.shape() || density.rank() != 3)
    throw Error("volume metrics: densities " + toString(density.shape()) + " and " + toString(reference.shape()) +
                " must be volumes [D, H, W] of one shape");
  return std::sqrt(reduced(context, ops::ReduceMap::SquaredDifference, density, &reference, 1.0 / static_cast<double>(density.numel())));
}

double velocityRmse(Context& context, const Tensor& velocity, const Tensor& reference) {
  requireVelocity(velocity, "the velocity");
  if (velocity.shape() != reference.shape())
    throw Error("volume metrics: velocities " + toString(velocity.shape()) + " and " + toString(reference.shape()) +
                " differ in shape");
  const double cells = static_cast<double>(velocity.numel() / 3);
  return std::sqrt(reduced(context, ops::ReduceMap::SquaredDifference, velocity, &reference, 1.0 / cells));
}

VelocityScores velocityScores(Context& context, const Tensor& velocity) {
  requireVelocity(velocity, "the velocity");
  const Shape volume{velocity.size(1), velocity.size(2), velocity.size(3)};
  const double cells = static_cast<double>(numElements(volume));
  const Tensor divergence(context, volume), zero(context, volume), centred(context, velocity.shape()),
      gradient(context, volume);
  Stream stream(context);
  physics::divergence(stream, velocity, physics::Staggering::Mac, divergence);
  stream.fillZero(zero);
  physics::macToCentred(stream, velocity, centred);
  physics::gradientNormSquared(stream, centred, gradient);
  stream.submit();
  return {reduced(context, ops::ReduceMap::AbsoluteDifference, divergence, &zero, 1.0 / cells),
          reduced(context, ops::ReduceMap::Identity, gradient, nullptr, 1.0 / cells)};
}

}  // namespace smokesvd::eval

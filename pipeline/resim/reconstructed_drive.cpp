#include "pipeline/resim/reconstructed_drive.h"

#include <cmath>

#include "nets/ops/elementwise.h"
#include "nets/ops/reduce.h"
#include "pipeline/physics/advection.h"
#include "pipeline/resim/upsample.h"
#include "pipeline/sim/domain.h"
#include "runtime/error.h"
#include "runtime/stream.h"

namespace smokesvd::resim {

ReconstructedDrive::ReconstructedDrive(Context& context, const sim::SavedRun& reconstruction, int upres,
                                       double inflowScale)
    : context_(context),
      reconstruction_(reconstruction),
      upres_(upres),
      inflowScale_(static_cast<float>(inflowScale)),
      grid_(finerGrid(reconstruction.grid(), upres)) {
  sim::Scene domain = reconstruction.scene;
  domain.resolution = grid_;
  domain.obstacles.clear();
  flags_ = Tensor::fromHost(context, grid_.volume(), sim::sceneFlags(domain, 0));
  {
    Stream stream(context);
    flagGrid_ = std::make_unique<physics::FlagGrid>(stream, flags_);
    stream.submit();
  }
  physics::PressureOptions pressure;
  pressure.tolerance = domain.pressureTolerance;
  pressure.maxIterations = 200;
  solver_ = std::make_unique<physics::PressureSolver>(context, flags_, pressure);
  const int frames = reconstruction.frames;
  forceWindow_ = {std::max(0, frames - 2 - kMeanWindow), frames - 3};
  inflowWindow_ = {std::max(1, frames - kMeanWindow), frames - 1};
  forceSum_ = Tensor(context, grid_.vector());
  inflowSum_ = Tensor(context, grid_.volume());
  Stream stream(context);
  ops::fill(stream, forceSum_, 0.0f);
  ops::fill(stream, inflowSum_, 0.0f);
  stream.submit();
}

Tensor ReconstructedDrive::upsampledVelocity(int frame) const {
  const Tensor coarse = Tensor::fromHost(context_, reconstruction_.grid().vector(), reconstruction_.velocity(frame));
  Stream stream(context_);
  Tensor fine = upsampleVelocity(stream, coarse, upres_);
  stream.submit();
  return fine;
}

Tensor ReconstructedDrive::projected(const Tensor& velocity) {
  Tensor out(context_, grid_.vector());
  solver_->project(velocity, out);
  const Tensor difference(context_, grid_.vector()), removed(context_, {1}), whole(context_, {1});
  Stream stream(context_);
  ops::binary(stream, ops::BinaryOp::Sub, velocity, out, difference);
  ops::mul(stream, difference, difference, difference);
  ops::reduceAll(stream, ops::Reduction::Sum, difference, removed);
  ops::mul(stream, velocity, velocity, difference);
  ops::reduceAll(stream, ops::Reduction::Sum, difference, whole);
  stream.submit();
  const double norm = whole.download()[0];
  removed_.push_back(norm > 0 ? std::sqrt(removed.download()[0] / norm) : 0.0);
  return out;
}

std::vector<float> ReconstructedDrive::initialDensity() const {
  const Tensor coarse = Tensor::fromHost(context_, reconstruction_.grid().volume(), reconstruction_.density(0));
  Stream stream(context_);
  const Tensor fine = upsampleVolume(stream, coarse, upres_);
  stream.submit();
  return fine.download();
}

std::vector<float> ReconstructedDrive::initialVelocity() const {
  if (reconstruction_.frames < 2) return std::vector<float>(static_cast<std::size_t>(3 * grid_.cells()), 0.0f);
  return upsampledVelocity(0).download();
}

Tensor ReconstructedDrive::forceAt(int t) {
  if (!previous_.defined()) previous_ = projected(upsampledVelocity(t));
  const Tensor next = projected(upsampledVelocity(t + 1));
  Tensor force(context_, grid_.vector());
  Stream stream(context_);
  physics::advect(stream, *flagGrid_, previous_, previous_, nullptr, physics::AdvectionParams{}, force);
  ops::binary(stream, ops::BinaryOp::Sub, next, force, force);
  if (t >= forceWindow_.first) ops::add(stream, forceSum_, force, forceSum_);
  stream.submit();
  previous_ = next;
  return force;
}

StepInputs ReconstructedDrive::next() {
  const int t = step_++;
  const int frames = reconstruction_.frames;
  StepInputs inputs;
  if (t <= frames - 3) {
    inputs.force = forceAt(t);
  } else if (forceWindow_.count() > 0) {
    if (!forceMean_) {
      Stream stream(context_);
      ops::scale(stream, forceSum_, 1.0f / static_cast<float>(forceWindow_.count()), forceSum_);
      stream.submit();
      forceMean_ = true;
    }
    inputs.force = forceSum_;
  }
  if (t + 1 <= frames - 1) {
    const Tensor coarse = Tensor::fromHost(context_, reconstruction_.grid().volume(), reconstruction_.inflow(t + 1));
    Stream stream(context_);
    inputs.inflow = upsampleVolume(stream, coarse, upres_);
    ops::scale(stream, inputs.inflow, inflowScale_, inputs.inflow);
    if (t + 1 >= inflowWindow_.first) ops::add(stream, inflowSum_, inputs.inflow, inflowSum_);
    stream.submit();
  } else if (inflowWindow_.count() > 0) {
    if (!inflowMean_) {
      Stream stream(context_);
      ops::scale(stream, inflowSum_, 1.0f / static_cast<float>(inflowWindow_.count()), inflowSum_);
      stream.submit();
      inflowMean_ = true;
    }
    inputs.inflow = inflowSum_;
  }
  return inputs;
}

nlohmann::json ReconstructedDrive::describe() const {
  auto window = [](const Window& w) -> nlohmann::json {
    if (w.count() == 0) return "none (the clip is too short)";
    return {w.first, w.last};
  };
  return {{"velocity", "the reconstruction's, frames 0.." + std::to_string(std::max(reconstruction_.frames - 2, 0)) +
                           ", as the force that reproduces it (docs/applications.md)"},
          {"force_after_the_reconstruction", {{"mean_of_frames", window(forceWindow_)}}},
          {"inflow_after_the_reconstruction", {{"mean_of_frames", window(inflowWindow_)}}},
          {"removed_by_projection", removed_},
          {"inflow_scale", inflowScale_},
          {"upres", upres_}};
}

}  // namespace smokesvd::resim

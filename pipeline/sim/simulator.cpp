#include "pipeline/sim/simulator.h"

#include <algorithm>

#include "nets/io/finite_values.h"
#include "nets/io/npy.h"
#include "nets/ops/elementwise.h"
#include "pipeline/physics/advection.h"
#include "pipeline/sim/domain.h"
#include "runtime/error.h"

namespace smokesvd::sim {

const char* const kBlownUp =
    "the simulation blew up; weaker forces (gravity, buoyancy, wind, force fields), a smaller dt or more "
    "steps_per_frame keep it finite";

namespace {

// A force field file as a planar acceleration [3, D, H, W], scaled.
Tensor loadForceField(Context& context, const ForceField& field, const GridSize& grid) {
  const std::string name = field.file.string();
  const io::NpyArray array =
      field.file.extension() == ".npz" ? io::readNpzMember(field.file, field.key) : io::readNpy(field.file);
  if (array.shape != Shape{grid.z, grid.y, grid.x, 3})
    throw Error(name + ": a force field must be [" + std::to_string(grid.z) + ", " + std::to_string(grid.y) + ", " +
                std::to_string(grid.x) + ", 3] (z, y, x, component) for this scene, got " + toString(array.shape));
  std::vector<float> values = array.toFloat();
  for (float& v : values) v *= static_cast<float>(field.scale);
  io::requireFiniteValues(values, array.shape, name, "a force field times its scale");
  Tensor interleaved = Tensor::fromHost(context, array.shape, values);
  Tensor planar(context, grid.vector());
  Stream stream(context);
  physics::interleavedToPlanar(stream, interleaved, planar);
  stream.submit();
  return planar;
}

// 1 where the flag has one of `bits`, else 0.
std::vector<float> flagMask(const std::vector<float>& flags, uint32_t bits) {
  std::vector<float> mask(flags.size());
  for (std::size_t i = 0; i < flags.size(); ++i) mask[i] = (static_cast<uint32_t>(flags[i]) & bits) != 0 ? 1.0f : 0.0f;
  return mask;
}

}  // namespace

Simulator::Simulator(Context& context, const Scene& scene)
    : context_(context),
      scene_(scene),
      grid_(scene.resolution),
      sources_(context, static_cast<int>(std::max<std::size_t>(scene.sources.size(), 1))) {
  const Shape volume = grid_.volume(), vector = grid_.vector();
  const std::vector<float> flags = sceneFlags(scene_, 0);
  flags_ = Tensor::fromHost(context, volume, flags);
  openMask_ = Tensor::fromHost(context, volume, flagMask(flags, physics::kFluid | physics::kEmpty));
  fluidMask_ = Tensor::fromHost(context, volume, flagMask(flags, physics::kFluid));
  density_ = Tensor(context, volume);
  densityNext_ = Tensor(context, volume);
  densityInflow_ = Tensor(context, volume);
  frameInflow_ = Tensor(context, volume);
  velocity_ = Tensor(context, vector);
  velocityScratch_[0] = Tensor(context, vector);
  velocityScratch_[1] = Tensor(context, vector);
  if (scene_.tracksTemperature()) {
    temperature_ = Tensor(context, volume);
    temperatureNext_ = Tensor(context, volume);
    temperatureInflow_ = Tensor(context, volume);
  }
  if (scene_.vorticity > 0) vorticity_ = Tensor(context, {4, grid_.z, grid_.y, grid_.x});
  for (const ForceField& field : scene_.forceFields) forceFields_.push_back(loadForceField(context, field, grid_));
  {
    Stream stream(context);
    ops::fill(stream, density_, 0.0f);
    ops::fill(stream, velocity_, 0.0f);
    ops::fill(stream, frameInflow_, 0.0f);
    if (temperature_.defined()) ops::fill(stream, temperature_, 0.0f);
    stream.submit();
  }
  physics::PressureOptions options;
  options.tolerance = scene_.pressureTolerance;
  options.maxIterations = scene_.pressureMaxIterations;
  solver_ = std::make_unique<physics::PressureSolver>(context, flags_, options);
  Stream stream(context);
  flagGrid_ = std::make_unique<physics::FlagGrid>(stream, flags_);
  stream.submit();
}

std::vector<physics::SourceState> Simulator::sourceStates(double time) const {
  std::vector<physics::SourceState> states;
  for (const Source& source : scene_.sources) {
    if (!source.frames.contains(frame_)) continue;
    physics::SourceState s;
    s.shape = source.shape.kind;
    s.centre = glm::vec3(source.shape.centre);
    s.size = glm::vec3(source.shape.size);
    s.axis = glm::vec3(source.shape.axis);
    s.mode = source.mode;
    s.density = static_cast<float>(source.density.at(time));
    s.temperature = static_cast<float>(source.temperature.at(time));
    s.setsVelocity = source.velocity.has_value();
    if (source.velocity) s.velocity = glm::vec3(source.velocity->at(time));
    s.noiseAmplitude = static_cast<float>(source.noise.amplitude);
    s.noiseScale = static_cast<float>(source.noise.scale);
    s.noiseSeed = source.noise.seed;
    for (int a = 0; a < 3; ++a) s.noiseOffset[a] = static_cast<float>(-source.noise.velocity[a] * time);
    states.push_back(s);
  }
  return states;
}

physics::Buoyancy Simulator::buoyancyAt(double time) const {
  physics::Buoyancy b;
  const Vec3 wind = scene_.wind.at(time);
  for (int a = 0; a < 3; ++a) {
    b.perDensity[a] = static_cast<float>(-scene_.gravity[a] * scene_.densityBuoyancy);
    b.perTemperature[a] = static_cast<float>(-scene_.gravity[a] * scene_.temperatureBuoyancy);
    if (scene_.windWeighting == WindWeighting::Density) b.perDensity[a] += static_cast<float>(wind[a]);
    else b.uniform[a] = static_cast<float>(wind[a]);
  }
  return b;
}

void Simulator::updateFlags(int frame) {
  const std::vector<float> flags = sceneFlags(scene_, frame);
  flags_.upload(flags);
  openMask_.upload(flagMask(flags, physics::kFluid | physics::kEmpty));
  fluidMask_.upload(flagMask(flags, physics::kFluid));
  solver_->setFlags(flags_);
  Stream stream(context_);
  flagGrid_ = std::make_unique<physics::FlagGrid>(stream, flags_);
  stream.submit();
}

physics::PressureReport Simulator::step(int substep) {
  const double time = frame_ + static_cast<double>(substep) / scene_.stepsPerFrame;
  const float dt = static_cast<float>(scene_.dt);
  const std::vector<physics::SourceState> states = sourceStates(time);
  sources_.write(states);
  const physics::AdvectionParams advection{scene_.advection, dt, static_cast<float>(scene_.advectionStrength)};
  const bool heat = temperature_.defined();

  Stream stream(context_);
  physics::inflowFields(stream, flags_, density_, heat ? &temperature_ : nullptr, sources_, dt, densityInflow_,
                        heat ? &temperatureInflow_ : nullptr);
  if (externalInflow_.defined()) {
    ops::mul(stream, externalInflow_, fluidMask_, densityNext_);
    ops::axpy(stream, 1.0f / static_cast<float>(scene_.stepsPerFrame), densityNext_, densityInflow_);
  }
  physics::advect(stream, *flagGrid_, density_, velocity_, &densityInflow_, advection, densityNext_);
  if (heat) physics::advect(stream, *flagGrid_, temperature_, velocity_, &temperatureInflow_, advection, temperatureNext_);
  // The velocity passes between two scratch fields; `current` is the latest.
  int current = 0;
  auto next = [&] { return velocityScratch_[1 - current]; };
  physics::advect(stream, *flagGrid_, velocity_, velocity_, nullptr, advection, velocityScratch_[current]);
  physics::addBuoyancy(stream, flags_, densityNext_, heat ? &temperatureNext_ : nullptr, velocityScratch_[current],
                       buoyancyAt(time), dt, next());
  current = 1 - current;
  if (vorticity_.defined()) {
    physics::vorticityField(stream, velocityScratch_[current], vorticity_);
    physics::addVorticityConfinement(stream, flags_, vorticity_, velocityScratch_[current],
                                     static_cast<float>(scene_.vorticity), dt, next());
    current = 1 - current;
  }
  for (std::size_t f = 0; f < forceFields_.size(); ++f) {
    if (!scene_.forceFields[f].frames.contains(frame_)) continue;
    physics::addForceField(stream, flags_, forceFields_[f], velocityScratch_[current], dt, next());
    current = 1 - current;
  }
  if (externalForce_.defined()) ops::axpy(stream, dt, externalForce_, velocityScratch_[current]);
  physics::applySourceVelocity(stream, flags_, sources_, velocityScratch_[current]);
  if (substep == 0) stream.copy(densityInflow_, frameInflow_);
  else ops::add(stream, frameInflow_, densityInflow_, frameInflow_);
  stream.submit();

  std::swap(density_, densityNext_);
  if (heat) std::swap(temperature_, temperatureNext_);
  return solver_->project(velocityScratch_[current], velocity_);
}

void Simulator::setExternalInflow(Tensor inflow) {
  if (inflow.defined()) physics::requireVolume(inflow, grid_, "simulator: external inflow");
  externalInflow_ = std::move(inflow);
}

void Simulator::setExternalForce(Tensor acceleration) {
  if (acceleration.defined()) physics::requireVector(acceleration, grid_, "simulator: external force");
  externalForce_ = std::move(acceleration);
}

physics::PressureReport Simulator::enforceDomain() {
  {
    Stream stream(context_);
    ops::mul(stream, density_, openMask_, density_);
    if (temperature_.defined()) ops::mul(stream, temperature_, openMask_, temperature_);
    stream.submit();
  }
  const physics::PressureReport report = solver_->project(velocity_, velocityScratch_[0]);
  std::swap(velocity_, velocityScratch_[0]);
  return report;
}

FrameReport Simulator::advanceFrame() {
  if (obstaclesChangeAt(scene_, frame_)) {
    updateFlags(frame_);
    enforceDomain();
  }
  FrameReport report;
  report.frame = frame_;
  for (int substep = 0; substep < scene_.stepsPerFrame; ++substep) {
    const physics::PressureReport pressure = step(substep);
    if (!pressure.finite)
      throw Error("frame " + std::to_string(frame_) + ", step " + std::to_string(substep) +
                  ": the velocity became NaN or infinite (" + std::string(kBlownUp) + ")");
    report.pressureIterations += pressure.iterations;
    report.relativeResidual = std::max(report.relativeResidual, pressure.relativeResidual);
    report.maxDivergence = pressure.residual;
    report.converged = report.converged && pressure.converged;
  }
  ++frame_;
  return report;
}

SimulatorState Simulator::state() const {
  SimulatorState s;
  s.frame = frame_;
  s.density = density_.download();
  s.velocity = velocity_.download();
  s.pressure = solver_->pressure();
  if (temperature_.defined()) s.temperature = temperature_.download();
  return s;
}

void Simulator::restore(const SimulatorState& s) {
  const std::size_t cells = static_cast<std::size_t>(grid_.cells());
  if (s.density.size() != cells || s.velocity.size() != 3 * cells || s.pressure.size() != cells ||
      s.temperature.size() != (temperature_.defined() ? cells : 0))
    throw Error("simulator: the saved state does not fit the scene's grid");
  frame_ = s.frame;
  updateFlags(std::max(frame_ - 1, 0));
  density_.upload(s.density);
  velocity_.upload(s.velocity);
  if (temperature_.defined()) temperature_.upload(s.temperature);
  solver_->setPressure(s.pressure);
}

}  // namespace smokesvd::sim

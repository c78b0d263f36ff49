#include "nets/optim/schedule.h"

#include <cmath>
#include <numbers>
#include <string>

#include "runtime/error.h"

namespace smokesvd::optim {

LrSchedule LrSchedule::constant(double lr, int64_t warmupSteps) {
  LrSchedule schedule;
  schedule.baseLr = lr;
  schedule.warmupSteps = warmupSteps;
  return schedule;
}

LrSchedule LrSchedule::step(double lr, int64_t stepSize, double gamma, int64_t warmupSteps) {
  LrSchedule schedule = constant(lr, warmupSteps);
  schedule.kind = ScheduleKind::Step;
  schedule.stepSize = stepSize;
  schedule.gamma = gamma;
  return schedule;
}

LrSchedule LrSchedule::cosine(double lr, int64_t cosineSteps, double minLr, int64_t warmupSteps) {
  LrSchedule schedule = constant(lr, warmupSteps);
  schedule.kind = ScheduleKind::Cosine;
  schedule.cosineSteps = cosineSteps;
  schedule.minLr = minLr;
  return schedule;
}

void LrSchedule::validate() const {
  const auto require = [](bool ok, const std::string& what) {
    if (!ok) throw Error("learning-rate schedule: " + what);
  };
  require(baseLr >= 0, "baseLr must be >= 0, got " + std::to_string(baseLr));
  require(warmupSteps >= 0, "warmupSteps must be >= 0, got " + std::to_string(warmupSteps));
  require(kind != ScheduleKind::Step || stepSize > 0, "stepSize must be > 0, got " + std::to_string(stepSize));
  require(kind != ScheduleKind::Step || gamma >= 0, "gamma must be >= 0, got " + std::to_string(gamma));
  require(kind != ScheduleKind::Cosine || cosineSteps > 0,
          "cosineSteps must be > 0, got " + std::to_string(cosineSteps));
  require(kind != ScheduleKind::Cosine || minLr >= 0, "minLr must be >= 0, got " + std::to_string(minLr));
}

double LrSchedule::at(int64_t stepsBefore) const {
  validate();
  const auto s = static_cast<double>(stepsBefore);
  if (stepsBefore < warmupSteps) return baseLr * (s + 1) / static_cast<double>(warmupSteps);
  const auto after = static_cast<double>(stepsBefore - warmupSteps);
  switch (kind) {
    case ScheduleKind::Constant: return baseLr;
    case ScheduleKind::Step: return baseLr * std::pow(gamma, std::floor(after / static_cast<double>(stepSize)));
    case ScheduleKind::Cosine: {
      const double progress = std::min(after, static_cast<double>(cosineSteps)) / static_cast<double>(cosineSteps);
      return minLr + (baseLr - minLr) * 0.5 * (1 + std::cos(std::numbers::pi * progress));
    }
  }
  return baseLr;
}

}  // namespace smokesvd::optim

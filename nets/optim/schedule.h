// Learning-rate schedules: an optional linear warm-up followed by a constant, step-decay or cosine
// schedule. The GPU evaluates them each step (shaders/nn/optimizer_step.comp); `at` is the same formula
// in double, for tests, logs and host-side use.
//
// s counts the steps taken before the current one (0 for the first), S = s - warmupSteps:
//   s < warmupSteps:  lr = baseLr (s + 1) / warmupSteps
//   Constant:         lr = baseLr
//   Step:             lr = baseLr gamma^floor(S / stepSize)                       (torch StepLR)
//   Cosine:           lr = minLr + (baseLr - minLr) (1 + cos(pi min(S, T) / T)) / 2 (torch CosineAnnealingLR's
//                     closed form, held at minLr after T = cosineSteps instead of rising again)
#pragma once

#include <cstdint>

namespace smokesvd::optim {

enum class ScheduleKind : int32_t { Constant = 0, Step = 1, Cosine = 2 };

struct LrSchedule {
  double baseLr = 1e-3;
  int64_t warmupSteps = 0;
  ScheduleKind kind = ScheduleKind::Constant;
  int64_t stepSize = 1;     // Step: decay every stepSize steps after the warm-up
  double gamma = 0.1;       // Step: decay factor
  int64_t cosineSteps = 1;  // Cosine: steps after the warm-up to reach minLr
  double minLr = 0.0;       // Cosine: final learning rate

  static LrSchedule constant(double lr, int64_t warmupSteps = 0);
  static LrSchedule step(double lr, int64_t stepSize, double gamma, int64_t warmupSteps = 0);
  static LrSchedule cosine(double lr, int64_t cosineSteps, double minLr = 0.0, int64_t warmupSteps = 0);

  // The learning rate of the step taken after `stepsBefore` steps. Throws Error if the schedule is invalid.
  double at(int64_t stepsBefore) const;
  // Throws Error naming the field if a count is not positive where it must be, or a rate is negative.
  void validate() const;
};

}  // namespace smokesvd::optim

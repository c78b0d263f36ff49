// Which MAC faces a force acts on (mantaflow's KnApplyForceField): the lower a-face of cell c, between
// m = c − e_a and c, takes a force when neither cell is an obstacle and at least one is fluid.
// Include after obstacle_flags.glsl.
#ifndef SMOKESVD_FORCE_FACES_GLSL
#define SMOKESVD_FORCE_FACES_GLSL

bool force_acts(uint flagC, uint flagM) {
  return !is_obstacle(flagC) && !is_obstacle(flagM) && (is_fluid(flagC) || is_fluid(flagM));
}

#endif

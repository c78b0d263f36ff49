// Slots of the pressure solver's scalar buffer (8 floats), written by pressure_scalars.comp and read
// by the conjugate-gradient kernels, so that an iteration runs without the host.
#ifndef SMOKESVD_PRESSURE_SCALARS_GLSL
#define SMOKESVD_PRESSURE_SCALARS_GLSL

const int SCALAR_RZ = 0;        // r·z of the current iteration
const int SCALAR_ALPHA = 1;     // step length rz / (p·Ap)
const int SCALAR_BETA = 2;      // direction update rz_new / rz_old (0 on the first iteration)
const int SCALAR_MAX_R = 3;     // max |r| over fluid cells
const int SCALAR_MAX_B = 4;     // max |b| = max |div u| before the solve
const int SCALAR_PAP = 5;       // p·Ap
const int SCALAR_MEAN_R = 6;    // mean of r over the fluid cells (closed domains remove it)

#endif

// Finite-difference checks of the scattering adjoints, on any context: the validated test context (float
// atomics where the device has them) and one that emulates them with compare-and-swap loops.
#pragma once

#include "pipeline/render/renderer.h"
#include "runtime/context.h"

namespace smokesvd::testing {

// render backward (march adjoint, and the shadow's with a light) against finite differences of the
// CPU reference, on a 6x7x5 grid seen by mixedCameras.
void expectRenderBackwardMatchesFiniteDifferences(Context& context, const render::RenderSettings& settings);

// lift backward against finite differences of the CPU reference, on a 9x7x5 grid seen by mixedCameras.
void expectLiftBackwardMatchesFiniteDifferences(Context& context);

}  // namespace smokesvd::testing

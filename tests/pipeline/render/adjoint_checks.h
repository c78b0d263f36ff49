// Finite-difference checks of the scattering adjoints, on any context: the validated test context (float
// atomics where the device has them) and one that emulates them with compare-and-swap loops.
#pragma once

#include "pipeline/render/renderer.h"
#include "runtime/context.h"

namespace smokesvd::testing {

// The cameras of a check: mixedCameras (orbit and perspective: the adjoints scatter with atomics), or orbit
// cameras with one pixel row per voxel row alone (ViewSet::raysInVoxelRows: on CPU devices the adjoints
// run by voxel planes, without atomics).
enum class CheckCameras { Mixed, VoxelRows };

// render backward (march adjoint, and the shadow's with a light) against finite differences of the
// CPU reference, on a 6x7x5 grid.
void expectRenderBackwardMatchesFiniteDifferences(Context& context, const render::RenderSettings& settings,
                                                  CheckCameras kind = CheckCameras::Mixed);

// lift backward against finite differences of the CPU reference, on a 9x7x5 grid.
void expectLiftBackwardMatchesFiniteDifferences(Context& context, CheckCameras kind = CheckCameras::Mixed);

}  // namespace smokesvd::testing

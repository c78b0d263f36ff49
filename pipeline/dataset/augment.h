// Augmentations that keep the physics consistent (every field of a sample transformed alike):
//   mirror in x:  f'(x) = f(W-1-x) for cell fields; for the MAC velocity u_x'(face i) = -u_x(face W-i)
//                 (face W, the wall's, is 0) and the other components mirrored like cells; a light's
//                 direction x -> -x. An orbit view at angle a of the mirrored volume is the view at -a
//                 of the original, flipped left to right, and renders made on the fly follow by themselves.
//   density scale: density and inflow times k (advection is linear in them; renders change look).
#pragma once

#include <vector>

#include "pipeline/render/renderer.h"
#include "runtime/geometry.h"

namespace smokesvd::dataset {

void mirrorCellsX(std::vector<float>& values, const GridSize& grid);     // [C, D, H, W], any C >= 1
void mirrorMacVelocityX(std::vector<float>& velocity, const GridSize& grid);  // [3, D, H, W]
void mirrorLookX(render::RenderSettings& look);
void scaleValues(std::vector<float>& values, float factor);

}  // namespace smokesvd::dataset

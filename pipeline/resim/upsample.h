// A reconstruction's fields on a grid k times finer along every axis (`smokesvd resim --upres k`):
//   scalar volumes (density, inflow): trilinear, F.interpolate(align_corners=False) (nets/ops/resample.h),
//     so values keep their units (density per cell);
//   MAC velocity: to cell centres, trilinear, times k (a velocity in cells per step of the coarse grid
//     moves k cells of the fine grid per step), back to MAC faces (pipeline/physics/differential.h).
// The upsampled velocity is not divergence-free on the fine grid; the re-simulation projects it.
// k = 1 returns copies of the fields unchanged.
#pragma once

#include "runtime/geometry.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::resim {

GridSize finerGrid(const GridSize& grid, int factor);

// [D, H, W] -> [kD, kH, kW] (new tensor).
Tensor upsampleVolume(Stream& stream, const Tensor& volume, int factor);
// MAC [3, D, H, W] -> MAC [3, kD, kH, kW] in cells of the fine grid per step (new tensor).
Tensor upsampleVelocity(Stream& stream, const Tensor& velocity, int factor);
// A cell-centred vector field [3, D, H, W] in cells per step (or per step²) -> [3, kD, kH, kW], trilinear
// and times k (new tensor).
Tensor upsampleCentred(Stream& stream, const Tensor& field, int factor);

}  // namespace smokesvd::resim

// The box of a volume outside which every trilinear lookup with zero padding reads only zeros, for the marches
// that take only the samples that can fall inside it (shaders/render/occupied_box.glsl):
//   blocks of 4^3 voxels, block k occupied when one of its voxels is non-zero;
//   box [2, 4]: low = (4 min k - 1/2, 0), high = (4 (max k + 1) + 1/2, 0) over the occupied blocks,
//   low = 1e30 and high = -1e30 where no block is.
// A march's samples outside it each add exactly 0, so leaving them out gives the same sum bit for bit. Two
// passes: block_occupancy.comp over the blocks, then occupied_box.comp in one workgroup.
#pragma once

#include "runtime/geometry.h"
#include "runtime/stream.h"

namespace smokesvd::render {

constexpr int64_t kOccupiedBlock = 4;  // OCCUPIED_BLOCK of occupied_box.glsl

// [ceil(D / 4), ceil(H / 4), ceil(W / 4)]: the blocks of a volume of `grid`.
Shape occupiedBlocksShape(const GridSize& grid);

// Writes whether each block of `volume` [D, H, W] (leading dimensions of size 1 allowed) is occupied (1) or not
// (0) into `occupied`, and the box they span into `box` [2, 4].
void occupiedBox(Stream& stream, const Tensor& volume, const Tensor& occupied, const Tensor& box);
// The box alone, in a new tensor.
Tensor occupiedBox(Stream& stream, const Tensor& volume);

}  // namespace smokesvd::render

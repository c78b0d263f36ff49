// The corners of every trilinear stencil's squares of a volume as vec4 texels (shaders/render/corner_quads.comp),
// so that a lookup reads two texels instead of eight scalars (sampling.glsl, sample_zero_quads):
//   quads[q(b)] = (v[b], v[b + x], v[b + y], v[b + x + y]),  b in [-1, W-1] x [-1, H-1] x [-1, D],
//   q(b) = ((b.z + 1)(H + 1) + b.y + 1)(W + 1) + b.x + 1,  v = 0 outside the volume.
// A kernel that makes many lookups of one volume (the shadow pass and its adjoint march every voxel to the
// boundary) builds them once: four floats per voxel, one cheap pass.
#pragma once

#include "runtime/geometry.h"
#include "runtime/stream.h"

namespace smokesvd::render {

// [(W + 1)(H + 1)(D + 2), 4]: the corner quads of a volume of `grid`.
Shape cornerQuadsShape(const GridSize& grid);

// Writes the corner quads of `volume` [D, H, W] (leading dimensions of size 1 allowed) into `quads`.
void cornerQuads(Stream& stream, const Tensor& volume, const Tensor& quads);
// The same into a new tensor.
Tensor cornerQuads(Stream& stream, const Tensor& volume);

}  // namespace smokesvd::render

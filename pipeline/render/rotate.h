// Rotation of a volume about the vertical line through its centre, trilinear with zero padding, and its
// adjoint (a gather). rotate(v, a) seen by the orbit camera at angle 0 is v seen by the orbit camera at
// angle a (pipeline/camera/camera.h):
//   out[c, q] = in[c](centre + R_a (c_q - centre)),  R_a (dx, dy, dz) = (dx cos a - dz sin a, dy, dx sin a + dz cos a)
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::render {

// volume [..., D, H, W] (leading dimensions are channels) -> rotated, same shape.
void rotate(Stream& stream, const Tensor& volume, double angleDegrees, const Tensor& rotated);
// gradRotated -> gradVolume (same shape; written, not accumulated).
void rotateBackward(Stream& stream, const Tensor& gradRotated, double angleDegrees, const Tensor& gradVolume);

}  // namespace smokesvd::render

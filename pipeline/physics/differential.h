// Grid differential operators and the MAC <-> cell-centred conversion, each with its adjoint
// (docs/physics.md). Velocities are planar [3, D, H, W] in cells per step, unit cell spacing.
// On cell-centred fields the difference along an axis is central inside and one-sided on the first
// and last cell (numpy.gradient); a MAC field's upper face past the last cell counts as 0.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::physics {

enum class Staggering { Mac, Centred };

// centred_d(c) = ½(mac_d(c) + mac_d(c + e_d)). Its adjoint is centredToMac.
void macToCentred(Stream& stream, const Tensor& mac, const Tensor& centred);
// mac_d(c) = ½(centred_d(c − e_d) + centred_d(c)). Its adjoint is macToCentred.
void centredToMac(Stream& stream, const Tensor& centred, const Tensor& mac);

// div [D, H, W]: MAC Σ_d u_d(c + e_d) − u_d(c); centred Σ_d ∂_d u_d.
void divergence(Stream& stream, const Tensor& velocity, Staggering staggering, const Tensor& out);
void divergenceBackward(Stream& stream, Staggering staggering, const Tensor& gradOut, const Tensor& gradVelocity);

// ω = ∇ × u [3, D, H, W] of a centred velocity.
void curl(Stream& stream, const Tensor& velocity, const Tensor& out);
void curlBackward(Stream& stream, const Tensor& gradOut, const Tensor& gradVelocity);

// |∇u|² per cell [D, H, W] of a centred velocity: Σ_k Σ_d (∂_d u_k)². With the divergence this is the
// paper's velocity loss L_vel = ‖∇·u‖² + ‖∇u‖² (summed over cells).
void gradientNormSquared(Stream& stream, const Tensor& velocity, const Tensor& out);
void gradientNormSquaredBackward(Stream& stream, const Tensor& velocity, const Tensor& gradOut,
                                 const Tensor& gradVelocity);

}  // namespace smokesvd::physics

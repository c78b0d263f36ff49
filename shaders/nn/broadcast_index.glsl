// Division by a divisor fixed for a dispatch, without integer division (which lavapipe does one lane at
// a time): the host passes (multiplier, shift) from fastDivisor() in nets/ops/broadcast.h, with
//   s = floor(log2 d), m = floor(2^(32+s) / d) + 1, or m = 0 when d = 2^s;
//   n / d = umulHigh(n, m) >> s (exact for n < 2^31), or n >> s when m = 0.
#ifndef SMOKESVD_BROADCAST_INDEX_GLSL
#define SMOKESVD_BROADCAST_INDEX_GLSL

uint divide(uint n, uvec2 divisor) {
  uint high, low;
  umulExtended(n, divisor.x, high, low);
  return (divisor.x == 0u ? n : high) >> divisor.y;
}

#endif

#include "nets/ops/dropout.h"

#include "nets/ops/elementwise.h"
#include "runtime/error.h"

namespace smokesvd::ops {

void dropout(Stream& stream, const Tensor& x, float p, uint64_t seed, const Tensor& y) {
  requireSameShape("dropout", {&x, &y});
  if (!(p >= 0.0f && p <= 1.0f)) throw Error("dropout: p = " + std::to_string(p) + " is not in [0, 1]");
  struct {
    uint32_t n, seedLow, seedHigh;
    float p, scale;
  } push{static_cast<uint32_t>(y.numel()), static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32), p,
         p < 1.0f ? 1.0f / (1.0f - p) : 0.0f};
  stream.dispatchFlat(stream.kernel("nn/dropout", {64, 1, 1}), {asVec4(x), y}, push,
                      (static_cast<uint64_t>(y.numel()) + 3) / 4);
}

}  // namespace smokesvd::ops

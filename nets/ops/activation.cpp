#include "nets/ops/activation.h"

#include "nets/ops/elementwise.h"

namespace smokesvd::ops {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{64, 1, 1};

void run(Stream& stream, Activation activation, bool backward, float negativeSlope, const Tensor& x,
         const Tensor& gy, const Tensor& out) {
  struct { uint32_t n; float slope; } push{static_cast<uint32_t>(out.numel()), negativeSlope};
  const Kernel& kernel =
      stream.kernel("nn/activation", kWorkgroup, {static_cast<int32_t>(activation), backward ? 1 : 0});
  stream.dispatchFlat(kernel, {asVec4(x), asVec4(gy), out}, push, (static_cast<uint64_t>(out.numel()) + 3) / 4);
}

}  // namespace

void activationForward(Stream& stream, Activation activation, float negativeSlope, const Tensor& x, const Tensor& y) {
  requireSameShape("activation", {&x, &y});
  run(stream, activation, false, negativeSlope, x, x, y);  // the gy binding is unused forward
}

void activationBackward(Stream& stream, Activation activation, float negativeSlope, const Tensor& x,
                        const Tensor& gy, const Tensor& gx) {
  requireSameShape("activation backward", {&x, &gy, &gx});
  run(stream, activation, true, negativeSlope, x, gy, gx);
}

}  // namespace smokesvd::ops

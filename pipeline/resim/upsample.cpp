#include "pipeline/resim/upsample.h"

#include "nets/ops/elementwise.h"
#include "nets/ops/resample.h"
#include "pipeline/physics/differential.h"
#include "pipeline/physics/grid.h"

namespace smokesvd::resim {

GridSize finerGrid(const GridSize& grid, int factor) {
  return {.x = grid.x * factor, .y = grid.y * factor, .z = grid.z * factor};
}

Tensor upsampleVolume(Stream& stream, const Tensor& volume, int factor) {
  const GridSize coarse = physics::volumeGrid(volume, "upsample: volume"), fine = finerGrid(coarse, factor);
  Tensor out(volume.context(), fine.volume());
  if (factor == 1) {
    ops::copy(stream, volume, out);
    return out;
  }
  const ops::Resample trilinear{ops::ResampleMode::Linear, false, factor};
  ops::resampleForward(stream, trilinear, volume.reshaped({1, 1, coarse.z, coarse.y, coarse.x}),
                       out.reshaped({1, 1, fine.z, fine.y, fine.x}));
  return out;
}

Tensor upsampleCentred(Stream& stream, const Tensor& field, int factor) {
  const GridSize coarse = physics::vectorGrid(field, "upsample: vector field"), fine = finerGrid(coarse, factor);
  Tensor out(field.context(), fine.vector());
  if (factor == 1) {
    ops::copy(stream, field, out);
    return out;
  }
  const ops::Resample trilinear{ops::ResampleMode::Linear, false, factor};
  ops::resampleForward(stream, trilinear, field.reshaped({1, 3, coarse.z, coarse.y, coarse.x}),
                       out.reshaped({1, 3, fine.z, fine.y, fine.x}));
  ops::scale(stream, out, static_cast<float>(factor), out);
  return out;
}

Tensor upsampleVelocity(Stream& stream, const Tensor& velocity, int factor) {
  const GridSize coarse = physics::vectorGrid(velocity, "upsample: velocity");
  Context& context = velocity.context();
  if (factor == 1) {
    Tensor out(context, coarse.vector());
    ops::copy(stream, velocity, out);
    return out;
  }
  const Tensor centred(context, coarse.vector());
  physics::macToCentred(stream, velocity, centred);
  const Tensor fineCentred = upsampleCentred(stream, centred, factor);
  Tensor out(context, finerGrid(coarse, factor).vector());
  physics::centredToMac(stream, fineCentred, out);
  return out;
}

}  // namespace smokesvd::resim

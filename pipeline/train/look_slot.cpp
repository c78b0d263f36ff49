#include "pipeline/train/look_slot.h"

#include "runtime/error.h"

namespace smokesvd::train {

LookSlot::LookSlot(Context& context) : look_(render::lookTensor(context, render::RenderSettings{})) {}

int LookSlot::upload(const render::RenderSettings& look) const {
  if (look.step != 1.0f || (look.light && look.light->step != 1.0f))
    throw Error("training: scenes must render with march steps of 1 voxel (their render.step)");
  render::uploadLook(look_, look);
  return look.light ? 1 : 0;
}

render::RenderSettings LookSlot::settings(bool lit) const {
  render::RenderSettings s;
  if (lit) s.light = render::DirectionalLight{};
  s.look = look_;
  return s;
}

}  // namespace smokesvd::train

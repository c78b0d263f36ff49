#include "pipeline/reconstruct/density_stage.h"

#include "nets/functional/activation.h"
#include "nets/functional/broadcast.h"
#include "nets/functional/concat.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/networks/view_slots.h"
#include "runtime/stream.h"

namespace smokesvd::reconstruct {
namespace {

using networks::kSlots;

// Rows `slots` of a slot stack [16, 1, h, w] as [n, 1, h, w].
Var gather(Tape& tape, const Var& images, const std::vector<int>& slots) {
  const Shape& s = images->value.shape();
  std::vector<Var> rows;
  for (const int slot : slots) rows.push_back(fn::sliceBatch(tape, images, slot, slot + 1));
  return fn::reshape(tape, fn::concatChannels(tape, rows), {static_cast<int64_t>(slots.size()), 1, s[2], s[3]});
}

Var presence(Tape& tape, const std::vector<std::pair<int, Var>>& known) {
  std::vector<float> p(kSlots, 0.0f);
  for (const auto& [slot, image] : known) p[static_cast<std::size_t>(slot)] = 1.0f;
  return variable(Tensor::fromHost(tape.context(), {kSlots}, p));
}

render::ViewSet viewsAt(Context& context, const Preset& preset, const std::vector<double>& angles) {
  std::vector<Camera> cameras;
  for (const double a : angles) cameras.push_back(networks::orbitCameraAt(preset, a));
  return render::uploadViews(context, cameras);
}

}  // namespace

DensityResult reconstructDensity(Context& context, MethodModels& models, const FrameState& state, int frame,
                                 const Tensor& front, const Tensor& side, const render::RenderSettings& look,
                                 const DensityOptions& options) {
  const Preset& preset = models.coarse->preset();
  Stream stream(context);
  Tape tape(stream);
  NoGrad noGrad(tape);
  std::vector<std::pair<int, Var>> known{{networks::kFrontSlot, variable(front)}, {networks::kSideSlot, variable(side)}};
  auto coarse = [&] { return models.coarse->forward(tape, models.coarse->slotImages(tape, known), presence(tape, known)).density; };
  Var density = coarse();
  DensityResult result;
  const render::ViewSet sideView = viewsAt(context, preset, {90.0});
  result.sideRender = diff::render(tape, density, sideView, look)->value;

  if (!options.refine) {
    const Var renders = diff::render(tape, density, models.coarse->views(), look);
    for (int slot = 0; slot < kSlots; ++slot)
      if (slot != networks::kFrontSlot && slot != networks::kSideSlot) known.emplace_back(slot, fn::sliceBatch(tape, renders, slot, slot + 1));
  } else {
    const Var previous = variable(state.refined1), beforePrevious = variable(state.refined2);
    std::vector<std::vector<int>> groups{networks::nearSlots(), networks::midSlots(), networks::farSlots()};
    if (!options.progressive) {
      std::vector<int> all;
      for (const auto& g : groups) all.insert(all.end(), g.begin(), g.end());
      groups = {all};
    }
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const std::vector<int>& slots = groups[g];
      // The group's views, then those at -beta and +beta: one render, the light's shadow made once.
      std::vector<double> angles;
      for (const double sign : {0.0, -1.0, 1.0})
        for (const int s : slots) angles.push_back(networks::slotAngle(s) + sign * models.refinerBeta);
      const Var all = diff::render(tape, density, viewsAt(context, preset, angles), look);
      const auto n = static_cast<int>(slots.size());
      const Var renders = fn::sliceBatch(tape, all, 0, n);
      const Var history1 = frame >= 2 ? gather(tape, previous, slots) : renders;
      const Var history2 = frame >= 2 ? gather(tape, beforePrevious, slots) : renders;
      const Var refined = fn::relu(
          tape, models.refiner->forward(tape, renders, fn::sliceBatch(tape, all, n, 2 * n), fn::sliceBatch(tape, all, 2 * n, 3 * n),
                                        history1, history2)
                    .refined);
      for (int i = 0; i < n; ++i) known.emplace_back(slots[static_cast<std::size_t>(i)], fn::sliceBatch(tape, refined, i, i + 1));
      if (g + 1 < groups.size()) density = coarse();
    }
    density = models.fine->forward(tape, models.fine->slotImages(tape, known), presence(tape, known)).density;
  }
  result.density = density->value;
  result.views = models.coarse->slotImages(tape, known)->value;
  stream.submit();
  return result;
}

}  // namespace smokesvd::reconstruct

#include "pipeline/train/sample_draw.h"

#include <algorithm>
#include <cmath>

#include "pipeline/dataset/augment.h"
#include "runtime/error.h"

namespace smokesvd::train {
namespace {

std::vector<const dataset::SceneEntry*> eligible(const std::vector<dataset::SceneEntry>& scenes, int frames,
                                                 int firstAtLeast) {
  std::vector<const dataset::SceneEntry*> out;
  for (const dataset::SceneEntry& s : scenes)
    if (s.frames >= firstAtLeast + frames) out.push_back(&s);
  if (out.empty())
    throw Error("dataset: no scene has the " + std::to_string(firstAtLeast + frames) + " frames a sample needs");
  return out;
}

}  // namespace

FrameDraw drawFrames(const std::vector<dataset::SceneEntry>& scenes, int frames, int firstAtLeast,
                     diffusion::Gaussian& random) {
  const auto candidates = eligible(scenes, frames, firstAtLeast);
  const auto pick = [&](std::size_t n) { return std::min(n - 1, static_cast<std::size_t>(random.uniform() * static_cast<double>(n))); };
  const dataset::SceneEntry* scene = candidates[pick(candidates.size())];
  const auto span = static_cast<std::size_t>(scene->frames - frames - firstAtLeast + 1);
  return {scene, firstAtLeast + static_cast<int>(pick(span))};
}

Augmentation drawAugmentation(const networks::DataSettings& data, diffusion::Gaussian& random) {
  Augmentation a;
  const double u = random.uniform(), v = random.uniform();
  a.mirror = data.mirror && u < 0.5;
  a.densityScale = static_cast<float>(
      std::exp(std::log(data.densityScaleMin) + v * (std::log(data.densityScaleMax) - std::log(data.densityScaleMin))));
  return a;
}

FrameDraw validationFrames(const std::vector<dataset::SceneEntry>& scenes, int k, int count, int frames, int firstAtLeast) {
  const auto candidates = eligible(scenes, frames, firstAtLeast);
  const dataset::SceneEntry* scene = candidates[static_cast<std::size_t>(k) % candidates.size()];
  const int perScene = std::max(1, (count + static_cast<int>(candidates.size()) - 1) / static_cast<int>(candidates.size()));
  const int round = k / static_cast<int>(candidates.size());
  const int span = scene->frames - frames - firstAtLeast + 1;
  // Frames spread evenly over the scene, offset by the scene so that scenes do not all use the same ones.
  const int frame = firstAtLeast + (span * (2 * round + 1) / (2 * perScene) + scene->index) % span;
  return {scene, frame};
}

namespace {
GridSize shapeOf(const dataset::SceneDataset& data) { return data.preset().grid; }
}  // namespace

std::vector<float> augmentedDensity(const dataset::SceneDataset& data, const dataset::SceneEntry& scene, int frame,
                                    const Augmentation& a) {
  std::vector<float> v = data.density(scene, frame);
  if (a.mirror) dataset::mirrorCellsX(v, shapeOf(data));
  dataset::scaleValues(v, a.densityScale);
  return v;
}

std::vector<float> augmentedInflow(const dataset::SceneDataset& data, const dataset::SceneEntry& scene, int frame,
                                   const Augmentation& a) {
  std::vector<float> v = data.inflow(scene, frame);
  if (a.mirror) dataset::mirrorCellsX(v, shapeOf(data));
  dataset::scaleValues(v, a.densityScale);
  return v;
}

std::vector<float> augmentedVelocity(const dataset::SceneDataset& data, const dataset::SceneEntry& scene, int frame,
                                     const Augmentation& a) {
  std::vector<float> v = data.velocity(scene, frame);
  if (a.mirror) dataset::mirrorMacVelocityX(v, shapeOf(data));
  return v;
}

std::vector<float> augmentedFlags(const dataset::SceneDataset& data, const dataset::SceneEntry& scene,
                                  const Augmentation& a) {
  std::vector<float> v = data.flags(scene);
  if (a.mirror) dataset::mirrorCellsX(v, shapeOf(data));
  return v;
}

render::RenderSettings augmentedLook(const dataset::SceneDataset& data, const dataset::SceneEntry& scene,
                                     const Augmentation& a) {
  render::RenderSettings look = data.look(scene);
  if (a.mirror) dataset::mirrorLookX(look);
  return look;
}

std::string describeData(const dataset::SceneDataset& data) {
  uint64_t low = UINT64_MAX, high = 0;
  for (const auto& s : data.training()) {
    low = std::min(low, s.scene.seed);
    high = std::max(high, s.scene.seed);
  }
  return std::to_string(data.training().size()) + " training scenes of " + data.root().string() + " (seeds " +
         std::to_string(low) + "-" + std::to_string(high) + "; " + std::to_string(data.validation().size()) +
         " held out for validation)";
}

}  // namespace smokesvd::train

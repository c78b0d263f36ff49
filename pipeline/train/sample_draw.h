// Drawing training samples: a scene, frames and the augmentation of one step, from the step's random
// numbers (trainer.h), and the fixed spread of validation samples.
#pragma once

#include <vector>

#include "nets/diffusion/gaussian.h"
#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/network_config.h"

namespace smokesvd::train {

struct Augmentation {
  bool mirror = false;
  float densityScale = 1.0f;
};

// A training scene with at least `frames` frames (Error if none has), and a first frame such that
// `frames` consecutive ones starting there exist and the first is >= `firstAtLeast`.
struct FrameDraw {
  const dataset::SceneEntry* scene = nullptr;
  int frame = 0;
};
FrameDraw drawFrames(const std::vector<dataset::SceneEntry>& scenes, int frames, int firstAtLeast,
                     diffusion::Gaussian& random);
Augmentation drawAugmentation(const networks::DataSettings& data, diffusion::Gaussian& random);

// The k-th of `count` validation samples: scenes in turn, frames spread over each scene.
FrameDraw validationFrames(const std::vector<dataset::SceneEntry>& scenes, int k, int count, int frames, int firstAtLeast);

// A frame's fields and the scene's look with the augmentation applied (augment.h).
std::vector<float> augmentedDensity(const dataset::SceneDataset& data, const dataset::SceneEntry& scene, int frame,
                                    const Augmentation& a);
std::vector<float> augmentedInflow(const dataset::SceneDataset& data, const dataset::SceneEntry& scene, int frame,
                                   const Augmentation& a);
std::vector<float> augmentedVelocity(const dataset::SceneDataset& data, const dataset::SceneEntry& scene, int frame,
                                     const Augmentation& a);  // MAC, planar
std::vector<float> augmentedFlags(const dataset::SceneDataset& data, const dataset::SceneEntry& scene,
                                  const Augmentation& a);
render::RenderSettings augmentedLook(const dataset::SceneDataset& data, const dataset::SceneEntry& scene,
                                     const Augmentation& a);

// "N training scenes of ROOT (seeds A-B)" for model cards.
std::string describeData(const dataset::SceneDataset& data);

}  // namespace smokesvd::train

// Differentiable rendering ops on the autograd tape (wrappers of pipeline/render):
//
//   Var render(Tape&, const Var& density, const render::ViewSet& views, const render::RenderSettings&);
//       density [D, H, W] -> images [V, 1, h, w]; backward gives d/d density (through the shadow too).
//   Var lift(Tape&, const Var& images, const render::ViewSet& views, const GridSize& grid);
//       images [V, 1, h, w] -> lifted [1, V, D, H, W] (views as channels, the density network's input).
//   Var rotate(Tape&, const Var& volume, double angleDegrees);
//       volume [..., D, H, W] -> the same shape, turned about the vertical axis (pipeline/render/rotate.h).
//
// Registered for `smokesvd op` as render, lift and rotate, with orbit cameras given by attribute `angles`
// (degrees, comma-separated) or calibrated cameras by `cameras` (a NeRF-style JSON file).
#pragma once

#include "nets/autograd/tape.h"
#include "pipeline/render/renderer.h"

namespace smokesvd::diff {

Var render(Tape& tape, const Var& density, const render::ViewSet& views, const render::RenderSettings& settings);
Var lift(Tape& tape, const Var& images, const render::ViewSet& views, const GridSize& grid);
Var rotate(Tape& tape, const Var& volume, double angleDegrees);

}  // namespace smokesvd::diff

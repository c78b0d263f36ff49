// Render benchmarks at the paper's size: 16 orbit views of a 64x112x64 volume at 112x64 pixels, forward and
// adjoint, with and without the shadowing light, of a smoke column that fills most of the grid and of a plume
// that leaves most of it empty; lifting and rotation of the column. Bytes count the
// tensors each run must read and write once (volume, shadow, images, gradients, camera table); the ray
// marcher's trilinear fetches re-read the volume many times, so the figure is an effective bandwidth.
#include <cmath>

#include "nets/ops/elementwise.h"
#include "pipeline/render/lift.h"
#include "pipeline/render/renderer.h"
#include "pipeline/render/rotate.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

const GridSize kGrid{.x = 64, .y = 112, .z = 64};
constexpr int kViews = 16, kWidth = 64, kHeight = 112;
const std::string kShape = "16 views 112x64 of 64x112x64";

render::RenderSettings settings(bool lit) {
  render::RenderSettings s;
  s.absorption = 0.5f;
  if (lit) {
    s.ambient = 0.3f;
    s.light = render::DirectionalLight{};
  }
  return s;
}

Tensor smoke(Context& context) {
  std::vector<float> values(static_cast<std::size_t>(kGrid.z * kGrid.y * kGrid.x));
  for (int z = 0; z < kGrid.z; ++z)
    for (int y = 0; y < kGrid.y; ++y)
      for (int x = 0; x < kGrid.x; ++x) {
        const double dx = (x - 32.0) / 12.0, dz = (z - 32.0) / 12.0;
        values[static_cast<std::size_t>((z * kGrid.y + y) * kGrid.x + x)] =
            static_cast<float>(std::exp(-(dx * dx + dz * dz)) * (y < 100 ? 1.0 : 0.0));
      }
  return Tensor::fromHost(context, kGrid.volume(), values);
}

// A plume as a fresh simulation holds one: a column of radius 10 voxels over the lower 70 of the 112 rows and
// zeros elsewhere, so that most of the grid is empty space, which the forward marches leave out
// (docs/rendering.md, "Empty space: the occupied box").
Tensor plume(Context& context) {
  std::vector<float> values(static_cast<std::size_t>(kGrid.z * kGrid.y * kGrid.x), 0.0f);
  for (int z = 0; z < kGrid.z; ++z)
    for (int y = 0; y < 70; ++y)
      for (int x = 0; x < kGrid.x; ++x) {
        const double dx = (x - 32.0) / 6.0, dz = (z - 32.0) / 6.0, squared = dx * dx + dz * dz;
        if (squared < (10.0 / 6.0) * (10.0 / 6.0))
          values[static_cast<std::size_t>((z * kGrid.y + y) * kGrid.x + x)] = static_cast<float>(std::exp(-squared));
      }
  return Tensor::fromHost(context, kGrid.volume(), values);
}

// The shadow pass, the render and its adjoint of `density`, named render/<prefix>shadow-pass,
// render/<prefix>forward[-lit] and render/<prefix>adjoint[-lit].
void marchBenchmarks(BenchContext& b, bool lit, const Tensor& density, const std::string& prefix) {
  Context& context = b.context();
  const render::ViewSet views = render::uploadViews(context, orbitCameras(orbitAngles(kViews), kGrid, kWidth, kHeight));
  const double volumeBytes = static_cast<double>(density.bytes());
  const double imageBytes = 4.0 * kViews * kWidth * kHeight;
  const double tableBytes = static_cast<double>(views.table.bytes());
  Tensor images(context, {kViews, 1, kHeight, kWidth});
  Tensor gradImages(context, {kViews, 1, kHeight, kWidth});
  Tensor gradDensity(context, density.shape());
  Tensor shadow(context, density.shape());
  Stream fill(context);
  ops::fill(fill, gradImages, 1.0f);
  fill.submit();
  {
    const render::RenderSettings s = settings(lit);
    const std::string suffix = lit ? "-lit" : "";
    if (lit) {
      b.measure("render/" + prefix + "shadow-pass", "64x112x64", 2 * volumeBytes, 0,
                [&](Stream& st) { render::lightTransmittance(st, density, s, shadow); });
      Stream prepare(context);
      render::lightTransmittance(prepare, density, s, shadow);
      prepare.submit();
    }
    const Tensor* shadowOrNull = lit ? &shadow : nullptr;
    // Forward: the full render (shadow pass included when lit).
    b.measure("render/" + prefix + "forward" + suffix, kShape, (lit ? 3 : 1) * volumeBytes + imageBytes + tableBytes, 0,
              [&](Stream& st) { render::render(st, density, views, s, images); });
    Stream forward(context);
    render::march(forward, density, shadowOrNull, views, s, images);
    forward.submit();
    // Adjoint: scatter march (+ shadow gather when lit); reads density, images, image gradient; writes gradients.
    b.measure("render/" + prefix + "adjoint" + suffix, kShape,
              (lit ? 6 : 2) * volumeBytes + 2 * imageBytes + tableBytes, 0, [&](Stream& st) {
                render::renderBackward(st, density, shadowOrNull, views, s, images, gradImages, gradDensity);
              });
  }
}

void liftRotateBenchmarks(BenchContext& b) {
  Context& context = b.context();
  const render::ViewSet views = render::uploadViews(context, orbitCameras(orbitAngles(kViews), kGrid, kWidth, kHeight));
  const Tensor density = smoke(context);
  const double volumeBytes = static_cast<double>(density.bytes());
  const double imageBytes = 4.0 * kViews * kWidth * kHeight;
  Tensor images(context, {kViews, 1, kHeight, kWidth});
  Tensor gradImages(context, {kViews, 1, kHeight, kWidth});
  Stream fill(context);
  ops::fill(fill, images, 0.5f);
  fill.submit();
  Tensor lifted(context, {kViews, kGrid.z, kGrid.y, kGrid.x});
  b.measure("render/lift", kShape, imageBytes + kViews * volumeBytes, 0,
            [&](Stream& st) { render::lift(st, images, views, kGrid, lifted); });
  b.measure("render/lift-adjoint", kShape, imageBytes + kViews * volumeBytes, 0,
            [&](Stream& st) { render::liftBackward(st, lifted, views, kGrid, gradImages); });
  Tensor rotated(context, density.shape());
  b.measure("render/rotate", "64x112x64 by 30 deg", 2 * volumeBytes, 0,
            [&](Stream& st) { render::rotate(st, density, 30.0, rotated); });
  b.measure("render/rotate-adjoint", "64x112x64 by 30 deg", 2 * volumeBytes, 0,
            [&](Stream& st) { render::rotateBackward(st, density, 30.0, rotated); });
}

const bool registered =
    registerBenchmark({"render/unlit", [](BenchContext& b) { marchBenchmarks(b, false, smoke(b.context()), ""); }}) &&
    registerBenchmark({"render/lit", [](BenchContext& b) { marchBenchmarks(b, true, smoke(b.context()), ""); }}) &&
    registerBenchmark({"render/plume-unlit", [](BenchContext& b) { marchBenchmarks(b, false, plume(b.context()), "plume-"); }}) &&
    registerBenchmark({"render/plume-lit", [](BenchContext& b) { marchBenchmarks(b, true, plume(b.context()), "plume-"); }}) &&
    registerBenchmark({"render/lift-rotate", liftRotateBenchmarks});

}  // namespace
}  // namespace smokesvd::bench

#include "tests/harness/simulated_reconstruction.h"

#include <fstream>

#include "nets/io/npy.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/run.h"
#include "pipeline/sim/scene.h"
#include "tests/harness/gpu_test.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;
constexpr int kWarmUp = 12;

void copyFile(const fs::path& from, const fs::path& to) {
  fs::create_directories(to.parent_path());
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}

}  // namespace

void writeSimulatedReconstruction(Context& context, const fs::path& folder, int frames, const GridSize& grid) {
  sim::Scene plume;
  plume.resolution = grid;
  plume.frames = kWarmUp + frames;
  plume.densityBuoyancy = 0.08;
  sim::Source source;
  const Vec3 size{static_cast<double>(grid.x), static_cast<double>(grid.y), static_cast<double>(grid.z)};
  source.shape.centre = {size[0] * 0.5, size[1] * 0.15, size[2] * 0.5};
  source.shape.size = {size[0] * 0.16, 0, 0};
  source.velocity = sim::Keyframes<Vec3>::constant({0, 0.5, 0});
  source.noise = {0.4, 2.0, {0, 0.5, 0}, 7};
  plume.sources.push_back(source);
  plume.render.width = static_cast<int>(grid.x);
  plume.render.height = static_cast<int>(grid.y);
  plume.render.absorption = 0.3 * 64.0 / size[0];
  const fs::path simulation = folder / "simulation";
  sim::runScene(context, plume, simulation, {});

  for (int t = 0; t < frames; ++t) {
    const std::string from = sim::frameName(kWarmUp + t), to = sim::frameName(t);
    for (const char* f : {"density", "velocity", "inflow"})
      copyFile(simulation / "fields" / (std::string(f) + "_" + from + ".npz"), folder / "fields" / (std::string(f) + "_" + to + ".npz"));
    for (int v = 0; v < plume.render.views; ++v) {
      char view[16];
      std::snprintf(view, sizeof view, "view_%02d", v);
      copyFile(simulation / "renders" / view / (from + ".png"), folder / "renders" / view / (to + ".png"));
    }
  }
  io::writeNpz(folder / "fields" / "inflow_0000.npz",
               {{"inflow", io::readNpzMember(folder / "fields" / "density_0000.npz", "density")}});
  copyFile(simulation / "flags.npz", folder / "flags.npz");
  fs::remove_all(simulation);

  sim::Scene box;
  box.resolution = grid;
  box.frames = frames;
  box.render = plume.render;
  sim::writeScene(folder / "scene.json", box);
  std::ofstream(folder / "run.json") << nlohmann::json{{"command", "smokesvd reconstruct"},
                                                        {"complete", true},
                                                        {"frames", frames},
                                                        {"signature", {{"framing", "box"}, {"source", {{"frame_rate", 24}}}}}}
                                            .dump(2);
}

SimulatedReconstructionScratch::SimulatedReconstructionScratch(const std::string& purpose, int frames)
    : root_(purpose), frames_(frames), reconstruction_(root_ / "recon") {}

const fs::path& SimulatedReconstructionScratch::reconstruction() {
  if (!written_) {
    writeSimulatedReconstruction(testContext(), reconstruction_, frames_);
    written_ = true;
  }
  return reconstruction_;
}

}  // namespace smokesvd::testing

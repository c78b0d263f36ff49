#include "pipeline/reconstruct/demo.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "nets/io/file_io.h"
#include "nets/io/npy.h"
#include "pipeline/media/video.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/reconstruct/reconstruction.h"
#include "pipeline/reconstruct/truth_comparison.h"
#include "pipeline/render/render_images.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "runtime/error.h"

namespace smokesvd::reconstruct {
namespace fs = std::filesystem;
namespace {

std::string row(const std::string& name, const TruthComparison& c) {
  char text[256];
  std::snprintf(text, sizeof text, "| %s | %.2f | %.2f | %.2f | %.4f |", name.c_str(), c.inputPsnr, c.sidePsnr, c.novelPsnr,
                c.densityRmse);
  return text;
}

}  // namespace

std::string runDemo(Context& context, const DemoOptions& o) {
  const Preset& p = preset(o.preset);
  const fs::path truth = o.out / "truth";
  sim::Scene scene = sim::randomScene(o.seed, p.grid, o.frames);
  scene.render.enabled = false;
  scene.render.width = p.imageWidth;
  scene.render.height = p.imageHeight;
  scene.render.absorption = p.absorption;
  scene.render.ambient = 1;
  scene.render.lightDirection.reset();
  if (!o.quiet) std::cerr << "demo: simulating a plume (seed " << o.seed << ", " << o.frames << " frames, " << p.name << ")\n";
  sim::runScene(context, scene, truth, {});

  render::RenderSettings look;
  look.absorption = p.absorption;
  const std::vector<Camera> front{networks::orbitCameraAt(p, 0)};
  std::vector<media::Image> frames;
  for (int t = 0; t < o.frames; ++t) {
    const io::NpyArray d = io::readNpzMember(truth / "fields" / ("density_" + sim::frameName(t) + ".npz"), "density");
    frames.push_back(render::renderImages(context, Tensor::fromHost(context, d.shape, d.toFloat()), front, look)[0]);
  }
  const fs::path video = truth / "front.mp4";
  media::writeVideo(video, frames, 30);

  struct Variant {
    std::string name, folder;
    bool synthesize, refine;
  };
  const std::vector<Variant> variants{{"SmokeSVD (full)", "full", true, true},
                                      {"mirrored front as side view", "mirror-side", false, true},
                                      {"no refinement", "no-refinement", true, false}};
  nlohmann::json results = nlohmann::json::object();
  std::ostringstream table;
  table << "| reconstruction | PSNR input view (dB) | PSNR side view (dB) | PSNR novel views (dB) | density RMSE |\n"
        << "|---|---|---|---|---|\n";
  TruthComparison floors;
  double seconds = 0;
  for (const Variant& v : variants) {
    ReconstructOptions r;
    r.input.input = video;
    r.input.framing = Framing::Box;
    r.input.intensity = "none";
    r.out = o.out / v.folder;
    r.models = o.models;
    r.preset = o.preset;
    r.resume = fs::exists(r.out / "run.json");
    r.quiet = o.quiet;
    r.sideView.synthesize = v.synthesize;
    r.density.refine = v.refine;
    if (!o.quiet) std::cerr << "demo: reconstructing (" << v.name << ")\n";
    const ReconstructResult result = runReconstruction(context, r);
    seconds += result.seconds;
    const TruthComparison c = compareWithTruth(context, r.out, truth, o.preset);
    floors = c;
    results[v.folder] = c.toJson();
    results[v.folder]["seconds"] = result.seconds;
    table << row(v.name, c) << "\n";
  }
  char floorRows[512];
  std::snprintf(floorRows, sizeof floorRows,
                "| floor: all-black image | %.2f | %.2f | %.2f | |\n| floor: input view as the view (mirrored for the side) | "
                "- | %.2f | %.2f | |\n",
                floors.blackInput, floors.blackSide, floors.blackNovel, floors.frontAsSide, floors.frontAsNovel);
  table << floorRows;
  std::ostringstream text;
  text << "# smokesvd demo\n\nA plume simulated with random scene seed " << o.seed << " (" << o.frames << " frames, preset "
       << p.name << ", " << p.grid.x << "x" << p.grid.y << "x" << p.grid.z << "), its front view rendered into "
       << "truth/front.mp4 and reconstructed from it; renders of each reconstruction against the truth's, "
       << p.imageWidth << "x" << p.imageHeight << " whole images, mean over frames. Device: " << context.info().name
       << "; reconstruction time " << seconds << " s in all.\n\n"
       << table.str();
  results["table"] = table.str();
  io::writeAtomically(o.out / "demo.json", [&](const fs::path& tmp) { std::ofstream(tmp) << results.dump(2) << "\n"; });
  io::writeAtomically(o.out / "demo.md", [&](const fs::path& tmp) { std::ofstream(tmp) << text.str(); });
  return text.str();
}

}  // namespace smokesvd::reconstruct

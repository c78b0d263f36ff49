// `smokesvd eval` end to end on the tiny preset (networks of tests/pipeline/tiny_models.h): a reconstruction
// whose fields are its truth's scores perfectly; a perturbed copy gives the figures a CPU reference computes
// from the renders; real footage (ScalarFlow, ../shared/data/scalarflow_real, skipped where absent): a
// reconstruction from 3 frames of train02.mp4 with its calibration, evaluated against all five cameras; bad
// inputs are one-line errors.
#include <gtest/gtest.h>

#include <fstream>

#include "nets/io/npy.h"
#include "pipeline/eval/evaluation.h"
#include "pipeline/eval/fields.h"
#include "pipeline/eval/footage_references.h"
#include "pipeline/eval/temporal_metrics.h"
#include "pipeline/media/video.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/reconstruct/reconstruction.h"
#include "pipeline/render/render_images.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "runtime/error.h"
#include "tests/harness/command.h"
#include "tests/harness/gpu_test.h"
#include "tests/pipeline/eval/metric_reference.h"
#include "tests/pipeline/tiny_models.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kFrames = 5;

const Preset& tiny() { return preset("tiny"); }

render::RenderSettings reconstructionLook() {
  render::RenderSettings look;
  look.absorption = tiny().absorption;
  return look;
}

// A tiny scene no network saw (seed 321), its fields on disk.
const fs::path& truthScene() {
  static const fs::path folder = [] {
    const fs::path root = tinyScratch("truth");
    sim::Scene scene = sim::randomScene(321, tiny().grid, kFrames);
    scene.render.enabled = false;
    sim::runScene(testContext(), scene, root, {});
    return root;
  }();
  return folder;
}

std::vector<float> truthDensity(int frame) {
  return eval::readTruthScene(truthScene()).density(frame, tiny().absorption);
}

// The reconstruction of the truth's front view, rendered with the reconstruction's look (--framing box,
// --intensity none): the box is the truth's.
const fs::path& reconstruction() {
  static const fs::path folder = [] {
    const fs::path frames = tinyScratch("front");
    const std::vector<Camera> front{networks::orbitCameraAt(tiny(), 0)};
    for (int t = 0; t < kFrames; ++t) {
      const Tensor density = Tensor::fromHost(testContext(), tiny().grid.volume(), truthDensity(t));
      media::writePng(frames / (sim::frameName(t) + ".png"), render::renderImages(testContext(), density, front, reconstructionLook())[0], 16);
    }
    reconstruct::ReconstructOptions o;
    o.input.input = frames;
    o.input.framing = reconstruct::Framing::Box;
    o.input.intensity = "none";
    o.out = tinyScratch("recon");
    o.models = tinyModels();
    o.preset = "tiny";
    o.quiet = true;
    o.videos = false;
    o.sideView.steps = 3;
    o.sideView.initSteps = 4;
    o.motion.inflowIterations = 2;
    reconstruct::runReconstruction(testContext(), o);
    return o.out;
  }();
  return folder;
}

// A copy of the reconstruction whose fields are replaced: density = scale * truth + offset (networks' units),
// velocity = velocityScale * truth velocity (MAC, as the file holds it).
fs::path replacedReconstruction(const std::string& name, float scale, float offset, float velocityScale) {
  const fs::path copy = tinyScratch(name);
  fs::copy(reconstruction(), copy, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const GridSize& g = tiny().grid;
  for (int t = 0; t < kFrames; ++t) {
    std::vector<float> density = truthDensity(t);
    for (float& v : density) v = scale * v + offset;
    io::writeNpz(copy / "fields" / ("density_" + sim::frameName(t) + ".npz"), {{"density", io::NpyArray::fromFloats(g.volume(), density)}});
    std::vector<float> velocity =
        io::readNpzMember(truthScene() / "fields" / ("velocity_" + sim::frameName(t) + ".npz"), "velocity").toFloat();
    for (float& v : velocity) v *= velocityScale;
    io::writeNpz(copy / "fields" / ("velocity_" + sim::frameName(t) + ".npz"),
                 {{"velocity", io::NpyArray::fromFloats({g.z, g.y, g.x, 3}, velocity)}});
  }
  return copy;
}

json readJson(const fs::path& path) {
  std::ifstream file(path);
  return json::parse(file);
}

std::string errorOf(Context& context, const eval::EvalOptions& o) {
  try {
    eval::runEvaluation(context, o);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The real ScalarFlow footage beside the repository, if present (../shared/data/scalarflow_real).
fs::path scalarflowFolder() {
  if (const char* dir = std::getenv("SMOKESVD_SCALARFLOW_DATA")) return dir;
  return fs::path(SMOKESVD_SOURCE_DIR) / ".." / "shared" / "data" / "scalarflow_real";
}

class EvalTest : public GpuTest {};

TEST_F(EvalTest, AReconstructionWithItsTruthsFieldsScoresPerfectly) {
  const fs::path perfect = replacedReconstruction("perfect", 1.0f, 0.0f, 1.0f);
  const fs::path out = tinyScratch("perfect_eval");
  const CommandResult r =
      runSmokesvd("eval " + perfect.string() + " --truth " + truthScene().string() + " --out " + out.string() + " --quiet");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("input: PSNR 100.00 dB"), std::string::npos) << r.out;
  for (const char* file : {"metrics.json", "metrics.csv", "per_frame.csv", "comparison.png"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  const json m = readJson(out / "metrics.json");
  ASSERT_EQ(m["views"].size(), 16u);
  for (const char* group : {"input", "side", "novel"}) {
    const json& g = m["image"][group];
    EXPECT_EQ(g["psnr"]["ours"].get<double>(), 100.0) << group;
    EXPECT_NEAR(g["ssim"]["ours"].get<double>(), 1.0, 1e-6) << group;
    EXPECT_EQ(g["rmse"]["ours"].get<double>(), 0.0) << group;
    EXPECT_LT(g["psnr"]["floor_black"].get<double>(), 60.0) << group;
    if (!eval::opticalFlowAvailable()) continue;
    const json& w = m["temporal"][group]["warp_error"];
    EXPECT_NEAR(w["ours"].get<double>(), w["reference"].get<double>(), 1e-12) << group;
  }
  if (!eval::opticalFlowAvailable()) {
    EXPECT_TRUE(m["temporal"].contains("not_computed"));
  }
  EXPECT_EQ(m["image"]["novel"]["views"].size(), 14u);
  EXPECT_TRUE(m["image"]["input"]["psnr"]["floor_input"].is_null());
  EXPECT_FALSE(m["image"]["side"]["psnr"]["floor_input"].is_null());
  EXPECT_LT(m["volume"]["density_rmse"]["ours"].get<double>(), 1e-7);
  EXPECT_GT(m["volume"]["density_rmse"]["floor_zero"].get<double>(), 1e-3);
  EXPECT_EQ(m["volume"]["velocity_rmse"]["ours"].get<double>(), 0.0);
  EXPECT_EQ(m["volume"]["velocity_rmse"]["frames"].get<int>(), kFrames - 1);
  EXPECT_DOUBLE_EQ(m["volume"]["mean_abs_divergence"]["ours"].get<double>(), m["volume"]["mean_abs_divergence"]["truth"].get<double>());
  EXPECT_DOUBLE_EQ(m["volume"]["mean_gradient_squared"]["ours"].get<double>(), m["volume"]["mean_gradient_squared"]["truth"].get<double>());
  for (const char* metric : {"LPIPS", "FID", "STYLE"}) EXPECT_TRUE(m["not_computed"].contains(metric)) << metric;
  std::ifstream perFrame(out / "per_frame.csv");
  int lines = 0;
  for (std::string line; std::getline(perFrame, line);) ++lines;
  EXPECT_EQ(lines, 1 + kFrames * 16);
}

TEST_F(EvalTest, APerturbedCopyGivesTheFiguresOfACpuReference) {
  const fs::path perturbed = replacedReconstruction("perturbed", 0.7f, 0.01f, 0.5f);
  eval::EvalOptions o;
  o.reconstruction = perturbed;
  o.truth = truthScene();
  o.out = tinyScratch("perturbed_eval");
  o.views = {"5", "8", "12"};
  o.quiet = true;
  const json m = eval::runEvaluation(context(), o);

  // The reference: renders of both densities through the same orbit cameras, metrics in double.
  const std::vector<int> slots{0, 5, 8, 12};
  std::vector<Camera> cameras;
  for (int s : slots) cameras.push_back(networks::orbitCameraAt(tiny(), networks::slotAngle(s)));
  struct Sums {
    double rmse = 0, psnr = 0, ssim = 0;
  };
  std::vector<std::array<Sums, 3>> sums(slots.size());
  const int w = tiny().imageWidth, h = tiny().imageHeight;
  const eval::ReconstructionRun run = eval::readReconstructionRun(perturbed);
  double densityRmse = 0, zeroRmse = 0, velocityRmse = 0, divergence = 0, divergenceTruth = 0, gradient = 0;
  const eval::TruthScene truth = eval::readTruthScene(truthScene());
  for (int t = 0; t < kFrames; ++t) {
    const std::vector<float> truthValues = truthDensity(t), ours = run.density(t);
    auto clamped = [&](const std::vector<float>& density) {
      const Tensor d = Tensor::fromHost(context(), tiny().grid.volume(), density);
      std::vector<media::Image> images = render::renderImages(context(), d, cameras, reconstructionLook());
      for (auto& image : images)
        for (float& v : image.values) v = std::clamp(v, 0.0f, 1.0f);
      return images;
    };
    const std::vector<media::Image> reference = clamped(truthValues), rendered = clamped(ours);
    for (std::size_t v = 0; v < slots.size(); ++v) {
      const media::Image input = networks::slotAngle(slots[v]) >= 90 ? eval::mirrored(reference[0]) : reference[0];
      const std::vector<float> black(reference[v].values.size(), 0.0f);
      const std::vector<float>* candidates[3] = {&rendered[v].values, &black, &input.values};
      for (int c = 0; c < 3; ++c) {
        const double mse = referenceMse(*candidates[c], reference[v].values);
        sums[v][static_cast<std::size_t>(c)].rmse += std::sqrt(mse) / kFrames;
        sums[v][static_cast<std::size_t>(c)].psnr += referencePsnr(mse) / kFrames;
        sums[v][static_cast<std::size_t>(c)].ssim += referenceSsim(*candidates[c], reference[v].values, w, h) / kFrames;
      }
    }
    densityRmse += std::sqrt(referenceMse(ours, truthValues)) / kFrames;
    zeroRmse += std::sqrt(referenceMse(std::vector<float>(ours.size(), 0.0f), truthValues)) / kFrames;
    if (t < kFrames - 1) {
      const std::vector<float> u = run.velocity(t), uTruth = truth.velocity(t);
      velocityRmse += std::sqrt(3 * referenceMse(u, uTruth)) / (kFrames - 1);
      const int x = static_cast<int>(tiny().grid.x), y = static_cast<int>(tiny().grid.y), z = static_cast<int>(tiny().grid.z);
      divergence += referenceMeanAbsDivergence(u, x, y, z) / (kFrames - 1);
      divergenceTruth += referenceMeanAbsDivergence(uTruth, x, y, z) / (kFrames - 1);
      gradient += referenceMeanGradientSquared(u, x, y, z) / (kFrames - 1);
    }
  }
  const char* names[] = {"view_00", "view_05", "view_08", "view_12"};
  const char* candidates[] = {"ours", "floor_black", "floor_input"};
  for (std::size_t v = 0; v < slots.size(); ++v) {
    const json& view = m["image"]["per_view"][names[v]];
    for (int c = 0; c < 3; ++c) {
      if (v == 0 && c == 2) {
        EXPECT_TRUE(view["psnr"]["floor_input"].is_null());
        continue;
      }
      const Sums& s = sums[v][static_cast<std::size_t>(c)];
      EXPECT_NEAR(view["rmse"][candidates[c]].get<double>(), s.rmse, 1e-5) << names[v] << " " << candidates[c];
      EXPECT_NEAR(view["psnr"][candidates[c]].get<double>(), s.psnr, 2e-3) << names[v] << " " << candidates[c];
      EXPECT_NEAR(view["ssim"][candidates[c]].get<double>(), s.ssim, 2e-5) << names[v] << " " << candidates[c];
    }
  }
  // A group's figure is the mean of its views'.
  EXPECT_NEAR(m["image"]["novel"]["psnr"]["ours"].get<double>(),
              0.5 * (m["image"]["per_view"]["view_05"]["psnr"]["ours"].get<double>() + m["image"]["per_view"]["view_12"]["psnr"]["ours"].get<double>()),
              1e-9);
  EXPECT_EQ(m["views"].size(), 4u);
  EXPECT_NEAR(m["volume"]["density_rmse"]["ours"].get<double>(), densityRmse, 1e-5);
  EXPECT_NEAR(m["volume"]["density_rmse"]["floor_zero"].get<double>(), zeroRmse, 1e-5);
  EXPECT_NEAR(m["volume"]["velocity_rmse"]["ours"].get<double>(), velocityRmse, 1e-5);
  EXPECT_NEAR(m["volume"]["mean_abs_divergence"]["ours"].get<double>(), divergence, 1e-5);
  EXPECT_NEAR(m["volume"]["mean_abs_divergence"]["truth"].get<double>(), divergenceTruth, 1e-5);
  EXPECT_NEAR(m["volume"]["mean_gradient_squared"]["ours"].get<double>(), gradient, 1e-5);
}

TEST_F(EvalTest, RealFootageThroughEveryCalibratedCamera) {
  const fs::path data = scalarflowFolder();
  if (!fs::exists(data / "info.json") || !fs::exists(data / "train02.mp4"))
    GTEST_SKIP() << "the ScalarFlow footage is not at " << data << " (see ../shared/data/scalarflow_real/README.md)";
  if (!media::findFfmpeg()) GTEST_SKIP() << "ffmpeg not installed";
  reconstruct::ReconstructOptions r;
  r.input.input = data / "train02.mp4";
  r.input.count = 3;
  r.input.framing = reconstruct::Framing::Calibrated;
  r.input.calibration = data / "info.json";
  r.out = tinyScratch("real_recon");
  r.models = tinyModels();
  r.preset = "tiny";
  r.quiet = true;
  r.videos = false;
  r.sideView.steps = 3;
  r.sideView.initSteps = 4;
  r.motion.inflowIterations = 2;
  reconstruct::runReconstruction(context(), r);

  // The input camera's reference is exactly the input the reconstruction saw.
  const eval::ReconstructionRun run = eval::readReconstructionRun(r.out);
  eval::FootageOptions f;
  f.calibration = data / "info.json";
  f.videos = data;
  eval::FootageReferences references(run, f);
  ASSERT_EQ(references.views().size(), 6u);
  std::size_t input = 0;
  for (std::size_t v = 0; v < references.views().size(); ++v)
    if (references.views()[v].group == eval::ViewGroup::Input) input = v;
  EXPECT_EQ(input, 0u);
  EXPECT_EQ(references.views()[input].name, "train02.mp4");
  for (int t = 0; t < 3; ++t) {
    const std::vector<media::Image> images = references.frame(context(), t);
    const media::Image recorded = media::readPng(r.out / "input" / (sim::frameName(t) + ".png"));
    ASSERT_EQ(images[input].values.size(), recorded.values.size());
    for (std::size_t i = 0; i < recorded.values.size(); ++i) ASSERT_NEAR(images[input].values[i], recorded.values[i], 1e-4) << i;
  }

  eval::EvalOptions o;
  o.reconstruction = r.out;
  o.cameras = data / "info.json";
  o.videos = data;
  o.out = tinyScratch("real_eval");
  o.quiet = true;
  const json m = eval::runEvaluation(context(), o);
  EXPECT_EQ(m["image"]["novel"]["views"].size(), 4u);
  EXPECT_FALSE(m["image"].contains("side"));
  if (eval::opticalFlowAvailable()) {
    EXPECT_TRUE(m["temporal"]["side"]["flow_mean"]["reference"].is_null());
  } else {
    EXPECT_TRUE(m["temporal"].contains("not_computed"));
  }
  for (const char* group : {"input", "novel"}) {
    const json& g = m["image"][group];
    // The networks trained for a few steps fill the box: only the floors have figures worth bounding.
    EXPECT_GE(g["psnr"]["ours"].get<double>(), 0.0) << group;
    EXPECT_GT(g["psnr"]["floor_black"].get<double>(), 15.0) << group;
    EXPECT_LT(g["psnr"]["floor_black"].get<double>(), 60.0) << group;
  }
  EXPECT_GT(m["image"]["novel"]["ssim"]["floor_input"].get<double>(), 0.0);
  EXPECT_TRUE(m["volume"]["density_rmse"]["ours"].is_null());
  EXPECT_GE(m["volume"]["mean_abs_divergence"]["ours"].get<double>(), 0.0);
  EXPECT_EQ(m["views"][input]["resolution"], json({tiny().imageWidth, tiny().imageHeight}));
  EXPECT_TRUE(fs::exists(o.out / "comparison.png"));

  // Whole frames at 54 x 96, in the footage's units: the black floor is that of the raw frames.
  o.region = eval::Region::Frame;
  o.width = 54;
  o.units = eval::Units::Footage;
  o.views = {"train00"};
  const json whole = eval::runEvaluation(context(), o);
  ASSERT_EQ(whole["views"].size(), 3u);  // train00, train02 (the input, always), the side view
  EXPECT_EQ(whole["views"][0]["name"], "train02.mp4");
  EXPECT_EQ(whole["views"][1]["resolution"], json({54, 96}));
  const std::vector<media::Image> frames = media::readVideoFrames(data / "train00.mp4", 0, 3);
  double psnr = 0;
  for (const media::Image& frame : frames) {
    const std::vector<float> small = reconstruct::resampleRegion(frame, {0, 0, 1080, 1920}, 54, 96);
    psnr += referencePsnr(referenceMse(std::vector<float>(small.size(), 0.0f), small)) / 3;
  }
  EXPECT_NEAR(whole["image"]["per_view"]["train00.mp4"]["psnr"]["floor_black"].get<double>(), psnr, 1e-3);
}

TEST_F(EvalTest, BadInputsAreOneLineErrors) {
  const fs::path scratch = tinyScratch("bad");
  auto expectError = [&](const eval::EvalOptions& o, const std::string& expected) {
    const std::string message = errorOf(context(), o);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  };
  eval::EvalOptions o;
  o.reconstruction = reconstruction();
  o.out = scratch / "out";
  o.quiet = true;

  // A truth of another resolution.
  sim::Scene other = sim::randomScene(5, {.x = 16, .y = 28, .z = 18}, 1);
  other.render.enabled = false;
  sim::runScene(context(), other, scratch / "other", {});
  o.truth = scratch / "other";
  expectError(o, "the truth is 16x28x18 cells, the reconstruction 16x28x16");

  // A truth with fewer frames than the reconstruction covers.
  fs::create_directories(scratch / "short" / "fields");
  fs::copy_file(truthScene() / "scene.json", scratch / "short" / "scene.json");
  for (int t = 0; t < 3; ++t)
    for (const char* field : {"density", "velocity"}) {
      const std::string name = std::string(field) + "_" + sim::frameName(t) + ".npz";
      fs::copy_file(truthScene() / "fields" / name, scratch / "short" / "fields" / name);
    }
  o.truth = scratch / "short";
  expectError(o, "the truth has 3 frames, the reconstruction covers input frames 0 to 4");

  // A camera file without the box.
  std::ofstream(scratch / "info.json") << R"({"train_videos": [{"file_name": "a.mp4", "camera_angle_x": 0.4,
      "camera_hw": [1920, 1080], "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}], "voxel_scale": [1, 1, 1]})";
  o.truth.clear();
  o.cameras = scratch / "info.json";
  o.videos = scratch;
  expectError(o, "info.json: field 'voxel_matrix': expected to be present");
  // A good camera file, but the reconstruction was not made with one.
  std::ofstream(scratch / "box.json") << R"({"train_videos": [{"file_name": "a.mp4", "camera_angle_x": 0.4,
      "camera_hw": [1920, 1080], "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}], "voxel_scale": [1, 1, 1],
      "voxel_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]})";
  o.cameras = scratch / "box.json";
  expectError(o, "needs a reconstruction made with --camera");

  // Neither or both references; a folder that is not a reconstruction.
  o.cameras.clear();
  o.videos.clear();
  expectError(o, "give either --truth SCENE_DIR or --cameras info.json with --videos DIR");
  o.truth = truthScene();
  o.reconstruction = truthScene();
  expectError(o, "not a reconstruction (its run.json was not written by smokesvd reconstruct)");
  o.reconstruction = reconstruction();
  o.views = {"17"};
  expectError(o, "--views: orbit views are 0 to 15, got 17");
  EXPECT_FALSE(fs::exists(scratch / "out"));

  const CommandResult cli = runSmokesvd("eval " + scratch.string() + " --truth " + truthScene().string() + " --out " + (scratch / "o").string());
  EXPECT_EQ(cli.exitCode, 1);
  EXPECT_EQ(cli.err.rfind("smokesvd: error: ", 0), 0u) << cli.err;
  EXPECT_EQ(std::count(cli.err.begin(), cli.err.end(), '\n'), 1) << cli.err;
}

}  // namespace
}  // namespace smokesvd::testing

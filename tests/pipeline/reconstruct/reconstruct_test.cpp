// `smokesvd reconstruct` end to end on the tiny preset with networks trained for a few steps
// (tests/pipeline/tiny_models.h): the files of a run, the physical relation of its fields, resume
// equivalence, the stage order, and bad inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "nets/io/file_io.h"
#include "nets/io/npy.h"
#include "pipeline/media/image.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/physics/advection.h"
#include "pipeline/reconstruct/reconstruction.h"
#include "pipeline/render/render_images.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"
#include "tests/pipeline/tiny_models.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

// The front view of a tiny density as the clip below shows it: the orbit camera at 0 degrees, the reference look.
media::Image clipRender(Context& context, const Tensor& density) {
  render::RenderSettings look;
  look.absorption = preset("tiny").absorption;
  const std::vector<Camera> front{networks::orbitCameraAt(preset("tiny"), 0)};
  return render::renderImages(context, density, front, look)[0];
}

// The front views of a tiny scene no network saw (seed 999), rendered with the reference look.
const fs::path& clip() {
  static const fs::path frames = [] {
    const fs::path root = tinyScratch("clip");
    sim::Scene scene = sim::randomScene(999, preset("tiny").grid, 6);
    scene.render.enabled = false;
    sim::runScene(testContext(), scene, root / "scene", {});
    for (int t = 0; t < 6; ++t) {
      const io::NpyArray d = io::readNpzMember(root / "scene" / "fields" / ("density_" + sim::frameName(t) + ".npz"), "density");
      const Tensor density = Tensor::fromHost(testContext(), d.shape, d.toFloat());
      fs::create_directories(root / "frames");
      media::writePng(root / "frames" / (sim::frameName(t) + ".png"), clipRender(testContext(), density), 16);
    }
    return root / "frames";
  }();
  return frames;
}

reconstruct::ReconstructOptions quickOptions(const fs::path& out) {
  reconstruct::ReconstructOptions o;
  o.input.input = clip();
  o.input.framing = reconstruct::Framing::Box;
  o.input.intensity = "none";
  o.out = out;
  o.models = tinyModels();
  o.preset = "tiny";
  o.quiet = true;
  o.sideView.steps = 3;
  o.sideView.initSteps = 4;
  o.motion.inflowIterations = 4;
  return o;
}

std::vector<float> field(const fs::path& run, const std::string& name, int frame) {
  return io::readNpzMember(run / "fields" / (name + "_" + sim::frameName(frame) + ".npz"), name).toFloat();
}

// density[t] = A(density[t-1], velocity[t-1]) + inflow[t] in run `out`, recomputed from its files with the
// advection kernel: bit for bit.
void expectFieldsObeyTheAdvection(Context& context, const fs::path& out, int frames) {
  const io::NpyArray flags = io::readNpzMember(out / "flags.npz", "flags");
  const GridSize grid = preset("tiny").grid;
  Stream stream(context);
  const physics::FlagGrid flagGrid(stream, Tensor::fromHost(context, grid.volume(), flags.toFloat()));
  stream.submit();
  for (int t = 1; t < frames; ++t) {
    const std::vector<float> interleaved = field(out, "velocity", t - 1);
    std::vector<float> planar(interleaved.size());
    const std::size_t cells = interleaved.size() / 3;
    for (std::size_t c = 0; c < cells; ++c)
      for (std::size_t a = 0; a < 3; ++a) planar[a * cells + c] = interleaved[3 * c + a];
    const Tensor previous = Tensor::fromHost(context, grid.volume(), field(out, "density", t - 1));
    const Tensor velocity = Tensor::fromHost(context, grid.vector(), planar);
    const Tensor inflow = Tensor::fromHost(context, grid.volume(), field(out, "inflow", t));
    const Tensor advected(context, grid.volume());
    Stream s(context);
    physics::advect(s, flagGrid, previous, velocity, &inflow, physics::AdvectionParams{}, advected);
    s.submit();
    const std::vector<float> expected = advected.download(), written = field(out, "density", t);
    for (std::size_t i = 0; i < written.size(); ++i)
      ASSERT_EQ(written[i], expected[i]) << "frame " << t << ", voxel " << i;
  }
}

// Mean squared difference between the clip's frames and renders of run `out`'s densities through the clip's
// camera and look, over frames 1 to frames-1.
double inputViewError(Context& context, const fs::path& out, int frames) {
  double sum = 0;
  std::size_t count = 0;
  for (int t = 1; t < frames; ++t) {
    const media::Image input = media::readPng(clip() / (sim::frameName(t) + ".png"));
    const Tensor density = Tensor::fromHost(context, preset("tiny").grid.volume(), field(out, "density", t));
    const media::Image render = clipRender(context, density);
    EXPECT_EQ(input.values.size(), render.values.size());
    for (std::size_t i = 0; i < std::min(input.values.size(), render.values.size()); ++i, ++count)
      sum += (input.values[i] - render.values[i]) * (input.values[i] - render.values[i]);
  }
  return sum / static_cast<double>(count);
}

class ReconstructTest : public GpuTest {};

TEST_F(ReconstructTest, WritesEveryOutputAndTheFieldsObeyTheAdvection) {
  const fs::path out = tinyScratch("full");
  const reconstruct::ReconstructResult r = reconstruct::runReconstruction(context(), quickOptions(out));
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(r.frames, 6);
  for (int t = 0; t < 6; ++t) {
    for (const char* f : {"density", "velocity", "inflow"})
      EXPECT_TRUE(fs::exists(out / "fields" / (std::string(f) + "_" + sim::frameName(t) + ".npz"))) << f << " " << t;
    for (int v = 0; v < 16; ++v) {
      char view[16];
      std::snprintf(view, sizeof view, "view_%02d", v);
      EXPECT_TRUE(fs::exists(out / "renders" / view / (sim::frameName(t) + ".png")));
    }
    EXPECT_TRUE(fs::exists(out / "side" / (sim::frameName(t) + ".png")));
    EXPECT_TRUE(fs::exists(out / "input" / (sim::frameName(t) + ".png")));
  }
  for (const char* f : {"run.json", "scene.json", "flags.npz", "contact.png", "input.mp4", "side.mp4", "orbit.mp4"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_FALSE(fs::exists(out / "checkpoint.npz"));

  expectFieldsObeyTheAdvection(context(), out, 6);
  std::ifstream runFile(out / "run.json");
  const nlohmann::json run = nlohmann::json::parse(runFile);
  EXPECT_EQ(run["stage_order"], nlohmann::json({"side_view", "density", "motion", "write"}));
  EXPECT_TRUE(run["complete"].get<bool>());
  for (const char* stage : {"side_view", "density", "motion", "write", "summaries"}) EXPECT_TRUE(run["stage_seconds"].contains(stage)) << stage;
  EXPECT_EQ(run["box"]["absorption"].get<double>(), static_cast<double>(preset("tiny").absorption));
}

// Frame 0's inflow is its whole density, as in the simulator's files; frame 1's inflow optimisation starts
// from no inflow (and is held to none), so with no iterations frame 1 adds nothing and its density is the
// advected frame 0 alone. (Starting from frame 0's inflow added the first plume again every frame.)
TEST_F(ReconstructTest, FrameOneStartsFromNoInflow) {
  const fs::path out = tinyScratch("no-inflow-iterations");
  reconstruct::ReconstructOptions o = quickOptions(out);
  o.input.count = 2;
  o.motion.inflowIterations = 0;
  o.videos = false;
  ASSERT_TRUE(reconstruct::runReconstruction(context(), o).complete);
  EXPECT_EQ(field(out, "inflow", 0), field(out, "density", 0));
  const std::vector<float> inflow = field(out, "inflow", 1);
  double density0 = 0;
  for (const float v : field(out, "density", 0)) density0 += v;
  ASSERT_GT(density0, 0.0);
  for (std::size_t i = 0; i < inflow.size(); ++i) ASSERT_EQ(inflow[i], 0.0f) << "voxel " << i;
}

TEST_F(ReconstructTest, AResumedRunEqualsAnUninterruptedOne) {
  const fs::path whole = tinyScratch("whole"), pieces = tinyScratch("pieces");
  reconstruct::ReconstructOptions o = quickOptions(whole);
  o.videos = false;
  reconstruct::runReconstruction(context(), o);
  o.out = pieces;
  o.stopAfter = 3;
  const reconstruct::ReconstructResult first = reconstruct::runReconstruction(context(), o);
  EXPECT_FALSE(first.complete);
  EXPECT_TRUE(fs::exists(pieces / "checkpoint.npz"));
  EXPECT_THROW(reconstruct::runReconstruction(context(), o), Error);  // neither --resume nor --overwrite
  o.stopAfter = -1;
  o.resume = true;
  const reconstruct::ReconstructResult second = reconstruct::runReconstruction(context(), o);
  EXPECT_TRUE(second.complete);
  EXPECT_EQ(second.framesThisCall, 3);
  int compared = 0;
  for (const auto& entry : fs::recursive_directory_iterator(whole / "fields")) {
    const fs::path relative = fs::relative(entry.path(), whole);
    ASSERT_TRUE(fs::exists(pieces / relative)) << relative;
    EXPECT_EQ(io::readFileBytes(entry.path()), io::readFileBytes(pieces / relative)) << relative;
    ++compared;
  }
  for (const auto& entry : fs::recursive_directory_iterator(whole / "renders"))
    if (entry.is_regular_file()) {
      const fs::path relative = fs::relative(entry.path(), whole);
      EXPECT_EQ(io::readFileBytes(entry.path()), io::readFileBytes(pieces / relative)) << relative;
      ++compared;
    }
  EXPECT_EQ(compared, 6 * 3 + 6 * 16);
}

TEST_F(ReconstructTest, AOneFrameClipReconstructs) {
  reconstruct::ReconstructOptions o = quickOptions(tinyScratch("one_frame"));
  o.input.count = 1;
  o.videos = false;
  const reconstruct::ReconstructResult r = reconstruct::runReconstruction(context(), o);
  EXPECT_TRUE(r.complete);
  EXPECT_TRUE(fs::exists(o.out / "fields" / "velocity_0000.npz"));
}

// --side-views: the given images are the side views, as they are (the clip's own frames stand in for
// side views here); a folder with another number of frames is an error naming it.
TEST_F(ReconstructTest, GivenSideViewsAreTheSideViews) {
  reconstruct::ReconstructOptions o = quickOptions(tinyScratch("given_side"));
  o.input.count = 3;
  o.videos = false;
  o.sideViews = clip();
  ASSERT_TRUE(reconstruct::runReconstruction(context(), o).complete);
  for (int t = 0; t < 3; ++t) {
    const std::vector<float> given = media::readPng(clip() / (sim::frameName(t) + ".png")).values;
    const std::vector<float> written = media::readPng(o.out / "side" / (sim::frameName(t) + ".png")).values;
    ASSERT_EQ(given.size(), written.size());
    for (std::size_t i = 0; i < given.size(); ++i) ASSERT_NEAR(written[i], given[i], 0.5f / 255) << "frame " << t << ", pixel " << i;
  }
  const fs::path two = tinyScratch("given_side_two");
  for (int t = 0; t < 2; ++t) fs::copy_file(clip() / (sim::frameName(t) + ".png"), two / (sim::frameName(t) + ".png"));
  o.sideViews = two;
  o.out = tinyScratch("given_side_mismatch");
  try {
    reconstruct::runReconstruction(context(), o);
    FAIL() << "2 side views for 3 frames were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("2 side views for 3 front views"), std::string::npos) << e.what();
  }
}

// Frames 0 and 1 come from SvDiff-init, conditioned on the front views alone: with two samples their side
// view is the mean of the side views of two one-sample runs whose seeds differ by 2^32.
TEST_F(ReconstructTest, SideSamplesAreTheMeanOfSeparateSamples) {
  auto sides = [&](const std::string& name, uint64_t seed, int samples) {
    reconstruct::ReconstructOptions o = quickOptions(tinyScratch(name));
    o.input.count = 2;
    o.videos = false;
    o.sideView.seed = seed;
    o.sideView.samples = samples;
    EXPECT_TRUE(reconstruct::runReconstruction(context(), o).complete) << name;
    std::vector<std::vector<float>> images;
    for (int t = 0; t < 2; ++t) images.push_back(media::readPng(o.out / "side" / (sim::frameName(t) + ".png")).values);
    return images;
  };
  const auto first = sides("side_samples_first", 5, 1), second = sides("side_samples_second", 5 + (uint64_t{1} << 32), 1);
  const auto mean = sides("side_samples_mean", 5, 2);
  for (int t = 0; t < 2; ++t) {
    ASSERT_EQ(mean[t].size(), first[t].size());
    double spread = 0;
    for (std::size_t i = 0; i < mean[t].size(); ++i) {
      ASSERT_NEAR(mean[t][i], 0.5f * (first[t][i] + second[t][i]), 1.5f / 65535) << "frame " << t << ", pixel " << i;
      spread += std::abs(first[t][i] - second[t][i]);
    }
    EXPECT_GT(spread, 0) << "frame " << t << ": the two seeds gave the same sample";
  }
}

std::string errorOf(Context& context, const reconstruct::ReconstructOptions& o) {
  try {
    reconstruct::runReconstruction(context, o);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// --polish fits each frame's velocity and inflow to the input through the renderer: the input view is
// matched more closely than without it, the fields still obey the advection bit for bit, and run.json
// records every polish setting (a resumed run must agree with them).
TEST_F(ReconstructTest, PolishMatchesTheInputBetterAndKeepsTheAdvection) {
  constexpr int kFrames = 4;
  const fs::path plain = tinyScratch("unpolished"), polished = tinyScratch("polished");
  reconstruct::ReconstructOptions o = quickOptions(plain);
  o.input.count = kFrames;
  o.videos = false;
  ASSERT_TRUE(reconstruct::runReconstruction(context(), o).complete);
  o.out = polished;
  o.polish.steps = 15;
  o.polish.lr = 0.05;
  o.polish.priorWeight = 0.5;
  ASSERT_TRUE(reconstruct::runReconstruction(context(), o).complete);
  expectFieldsObeyTheAdvection(context(), polished, kFrames);
  const double before = inputViewError(context(), plain, kFrames), after = inputViewError(context(), polished, kFrames);
  EXPECT_LT(after, before) << "input-view MSE without polish " << before << ", with it " << after;
  std::ifstream runFile(polished / "run.json");
  const nlohmann::json polish = nlohmann::json::parse(runFile)["signature"]["polish"];
  EXPECT_EQ(polish["steps"], 15);
  EXPECT_DOUBLE_EQ(polish["lr"].get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(polish["prior_weight"].get<double>(), 0.5);
}

TEST_F(ReconstructTest, BadInputsAreClearErrors) {
  const fs::path scratch = tinyScratch("bad");
  reconstruct::ReconstructOptions o = quickOptions(scratch / "out");
  std::ofstream(scratch / "not_a_video.mp4") << "hello";
  o.input.input = scratch / "not_a_video.mp4";
  EXPECT_NE(errorOf(context(), o).find("not_a_video.mp4"), std::string::npos);

  std::vector<float> values(3 * 28 * 16, 0.5f);
  values[100] = std::nanf("");
  io::writeNpy(scratch / "nan.npy", io::NpyArray::fromFloats({3, 28, 16}, values));
  o.input.input = scratch / "nan.npy";
  EXPECT_NE(errorOf(context(), o).find("frame 0, pixel (row 6, column 4) is not a finite number"), std::string::npos)
      << errorOf(context(), o);

  o = quickOptions(scratch / "out");
  o.input.first = 40;
  EXPECT_NE(errorOf(context(), o).find("no frames from frame 40"), std::string::npos) << errorOf(context(), o);

  o = quickOptions(scratch / "out");
  const fs::path partial = scratch / "models";
  fs::copy(tinyModels(), partial, fs::copy_options::recursive);
  fs::remove_all(partial / "svdiff");
  o.models = partial;
  EXPECT_NE(errorOf(context(), o).find("svdiff: no trained svdiff"), std::string::npos) << errorOf(context(), o);
  fs::copy(tinyModels() / "svdiff", partial / "svdiff", fs::copy_options::recursive);
  fs::copy_file(tinyModels() / "gu" / "model.safetensors", partial / "nvref" / "model.safetensors",
                fs::copy_options::overwrite_existing);
  const std::string mismatch = errorOf(context(), o);
  EXPECT_NE(mismatch.find("does not match"), std::string::npos) << mismatch;
  EXPECT_NE(mismatch.find("with a different shape"), std::string::npos) << mismatch;

  o = quickOptions(scratch / "file_not_folder" / "out");
  std::ofstream(scratch / "file_not_folder") << "x";
  EXPECT_NE(errorOf(context(), o).find("file_not_folder"), std::string::npos) << errorOf(context(), o);

  // A non-empty folder that is not a reconstruction is refused and left alone.
  fs::create_directories(scratch / "mine");
  std::ofstream(scratch / "mine" / "notes.txt") << "keep me";
  o = quickOptions(scratch / "mine");
  o.overwrite = true;
  EXPECT_NE(errorOf(context(), o).find("holds no reconstruction"), std::string::npos) << errorOf(context(), o);
  EXPECT_TRUE(fs::exists(scratch / "mine" / "notes.txt"));
}

}  // namespace
}  // namespace smokesvd::testing

// `smokesvd resim` on a simulated reconstruction (tests/harness/simulated_reconstruction.h: exact fields, seconds)
// and on a real one made by the tiny networks (tests/pipeline/tiny_models.h): no edits follow the
// reconstruction, obstacles hold no smoke, forces push it, a finer grid keeps the motion in its units, frames
// past the video keep being fed, and bad inputs are errors that touch nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "nets/io/npy.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/reconstruct/reconstruction.h"
#include "pipeline/render/render_images.h"
#include "pipeline/media/image.h"
#include "pipeline/resim/reconstructed_drive.h"
#include "pipeline/resim/resimulation.h"
#include "pipeline/sim/domain.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "pipeline/sim/saved_run.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/simulated_reconstruction.h"
#include "tests/pipeline/tiny_models.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 8;

const fs::path& simulated() {
  static const fs::path folder = [] {
    const fs::path root = tinyScratch("simulated-reconstruction");
    writeSimulatedReconstruction(testContext(), root, kFrames);
    return root;
  }();
  return folder;
}

resim::ResimOptions quick(const fs::path& out, const fs::path& source = simulated()) {
  resim::ResimOptions o;
  o.source = source;
  o.out = out;
  o.quiet = true;
  o.videos = false;
  return o;
}

std::vector<float> field(const fs::path& run, const std::string& name, int frame) {
  return io::readNpzMember(run / "fields" / (name + "_" + sim::frameName(frame) + ".npz"), name).toFloat();
}

[[maybe_unused]] double sum(const std::vector<float>& values) {
  double s = 0;
  for (const float v : values) s += v;
  return s;
}

// The density's centre of mass in cells of its grid (x, y, z).
[[maybe_unused]] Vec3 centreOfMass(const std::vector<float>& density, const GridSize& g) {
  Vec3 c{0, 0, 0};
  double mass = 0;
  for (int64_t k = 0; k < g.z; ++k)
    for (int64_t j = 0; j < g.y; ++j)
      for (int64_t i = 0; i < g.x; ++i) {
        const double d = density[static_cast<std::size_t>((k * g.y + j) * g.x + i)];
        c += d * Vec3{static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5, static_cast<double>(k) + 0.5};
        mass += d;
      }
  return c / mass;
}

class ResimTest : public GpuTest {};

TEST_F(ResimTest, WithoutEditsASimulatedReconstructionIsReproduced) {
  const fs::path out = tinyScratch("plain");
  const resim::ResimResult r = resim::runResimulation(context(), quick(out));
  EXPECT_TRUE(r.converged);
  ASSERT_EQ(r.departures.size(), static_cast<std::size_t>(kFrames));
  for (const resim::FrameDeparture& d : r.departures) {
    std::cout << "frame " << d.frame << ": relative L2 " << d.relativeL2 << ", max " << d.maxAbs << "\n";
    EXPECT_LT(d.relativeL2, 1e-5) << "frame " << d.frame;
  }
  for (int t = 0; t < kFrames; ++t) {
    for (const char* f : {"density", "velocity", "inflow"})
      EXPECT_TRUE(fs::exists(out / "fields" / (std::string(f) + "_" + sim::frameName(t) + ".npz"))) << f << " " << t;
    EXPECT_TRUE(fs::exists(out / "renders" / "view_15" / (sim::frameName(t) + ".png")));
  }
  const sim::SavedRun saved = sim::readSavedRun(out);
  EXPECT_EQ(saved.command, "smokesvd resim");
  EXPECT_EQ(saved.frames, kFrames);
  EXPECT_EQ(saved.frameRate, 24);
  EXPECT_EQ(saved.grid(), (GridSize{.x = 16, .y = 28, .z = 16}));
}

// The bound on a reconstruction by networks: the tiny preset's G_u, trained for a few steps, gives a
// velocity the projection removes most of (run.json's removed_by_projection, about 0.9), and the density
// departs by that motion; measured 0.063 after one frame, then about 0.13 more per frame (docs/applications.md).
TEST_F(ResimTest, WithoutEditsATrainedReconstructionIsFollowedForItsFirstFrames) {
  constexpr int frames = 5;
  const fs::path recon = tinyScratch("trained-reconstruction"), clip = tinyScratch("trained-clip");
  sim::Scene scene = sim::randomScene(999, preset("tiny").grid, frames);
  scene.render.enabled = false;
  sim::runScene(context(), scene, clip / "scene", {});
  render::RenderSettings look;
  look.absorption = preset("tiny").absorption;
  const std::vector<Camera> front{networks::orbitCameraAt(preset("tiny"), 0)};
  fs::create_directories(clip / "png");
  for (int t = 0; t < frames; ++t) {
    const Tensor density = Tensor::fromHost(context(), preset("tiny").grid.volume(), field(clip / "scene", "density", t));
    media::writePng(clip / "png" / (sim::frameName(t) + ".png"), render::renderImages(context(), density, front, look)[0], 16);
  }
  reconstruct::ReconstructOptions o;
  o.input.input = clip / "png";
  o.input.framing = reconstruct::Framing::Box;
  o.input.intensity = "none";
  o.out = recon;
  o.models = tinyModels();
  o.preset = "tiny";
  o.quiet = true;
  o.videos = false;
  o.sideView.steps = 3;
  o.sideView.initSteps = 4;
  o.motion.inflowIterations = 4;
  reconstruct::runReconstruction(context(), o);

  const fs::path out = tinyScratch("trained-resim");
  const resim::ResimResult r = resim::runResimulation(context(), quick(out, recon));
  EXPECT_TRUE(r.converged);
  ASSERT_EQ(r.departures.size(), static_cast<std::size_t>(frames));
  EXPECT_LT(r.departures[0].relativeL2, 1e-6);
  for (int t = 1; t < frames; ++t) {
    const resim::FrameDeparture& d = r.departures[static_cast<std::size_t>(t)];
    std::cout << "frame " << t << ": relative L2 " << d.relativeL2 << ", max " << d.maxAbs << "\n";
    EXPECT_LT(d.relativeL2, 0.1 + 0.15 * (t - 1)) << "frame " << t;
  }
  std::ifstream runFile(out / "run.json");
  const nlohmann::json removed = nlohmann::json::parse(runFile)["drive"]["removed_by_projection"];
  ASSERT_EQ(removed.size(), static_cast<std::size_t>(frames - 1));
  for (const auto& fraction : removed) EXPECT_TRUE(fraction.get<double>() >= 0 && fraction.get<double>() <= 1) << fraction;
}

// The cells of `grid` inside the sphere (grid coordinates).
std::vector<std::size_t> cellsInside(const GridSize& g, const Vec3& centre, double radius) {
  std::vector<std::size_t> cells;
  for (int64_t k = 0; k < g.z; ++k)
    for (int64_t j = 0; j < g.y; ++j)
      for (int64_t i = 0; i < g.x; ++i)
        if (glm::length(Vec3{static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5, static_cast<double>(k) + 0.5} - centre) <= radius)
          cells.push_back(static_cast<std::size_t>((k * g.y + j) * g.x + i));
  return cells;
}

TEST_F(ResimTest, AnObstacleHoldsNoDensityAndTheSmokeGoesAroundIt) {
  const GridSize grid{.x = 16, .y = 28, .z = 16};
  const Vec3 centre{8, 8, 8};
  resim::ResimOptions o = quick(tinyScratch("obstacle"));
  o.obstacles = {resim::parseObstacle("sphere:8,8,8,2.5@2")};
  resim::runResimulation(context(), o);
  const std::vector<std::size_t> inside = cellsInside(grid, centre, 2.5);
  ASSERT_FALSE(inside.empty());
  double before = 0;
  for (const std::size_t c : inside) before += field(simulated(), "density", 1)[c];
  EXPECT_GT(before, 1.0) << "the smoke should be where the obstacle will be";
  const sim::Scene scene = sim::readScene(o.out / "scene.json");
  ASSERT_EQ(scene.obstacles.size(), 1u);
  EXPECT_EQ(scene.obstacles[0].frames.first, 2);
  const std::vector<float> flags = sim::sceneFlags(scene, 2);
  const std::size_t cells = flags.size();
  for (int t = 2; t < kFrames; ++t) {
    const std::vector<float> density = field(o.out, "density", t), velocity = field(o.out, "velocity", t);
    for (const std::size_t c : inside) ASSERT_EQ(density[c], 0.0f) << "frame " << t << ", cell " << c;
    // No flow through the sphere: every face of an obstacle cell is at rest (the lower faces are stored with
    // the cell, the upper ones with the next cell along the axis).
    const int64_t strides[3] = {1, grid.x, grid.x * grid.y};
    for (const std::size_t c : inside)
      for (int a = 0; a < 3; ++a) {
        ASSERT_EQ(velocity[3 * c + static_cast<std::size_t>(a)], 0.0f) << "frame " << t << ", cell " << c;
        ASSERT_EQ(velocity[3 * (c + static_cast<std::size_t>(strides[a])) + static_cast<std::size_t>(a)], 0.0f);
      }
  }
  // The smoke passes it: density beside the sphere, in a ring at its height, at the last frame.
  const std::vector<float> last = field(o.out, "density", kFrames - 1);
  double beside = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    const int64_t i = static_cast<int64_t>(c) % grid.x, j = static_cast<int64_t>(c) / grid.x % grid.y,
                  k = static_cast<int64_t>(c) / (grid.x * grid.y);
    const double r = std::hypot(static_cast<double>(i) + 0.5 - centre[0], static_cast<double>(k) + 0.5 - centre[2]);
    if (std::abs(static_cast<double>(j) + 0.5 - centre[1]) < 1.5 && r > 2.5 && r < 4.5) beside += last[c];
  }
  EXPECT_GT(beside, 1.0);
}

TEST_F(ResimTest, AFinerGridKeepsTheMotionInItsOwnUnits) {
  resim::ResimOptions o = quick(tinyScratch("upres"));
  o.upres = 2;
  o.frames = 5;
  o.vorticity = 0.05;
  const resim::ResimResult r = resim::runResimulation(context(), o);
  EXPECT_TRUE(r.converged);
  EXPECT_TRUE(r.departures.empty());
  const GridSize coarse{.x = 16, .y = 28, .z = 16}, fine{.x = 32, .y = 56, .z = 32};
  EXPECT_EQ(io::readNpzMember(o.out / "fields" / "density_0004.npz", "density").shape, fine.volume());
  EXPECT_EQ(io::readNpzMember(o.out / "fields" / "velocity_0004.npz", "velocity").shape, (Shape{32, 56, 32, 3}));
  EXPECT_EQ(media::readPng(o.out / "renders" / "view_00" / "0004.png").width, 32);
  const sim::Scene scene = sim::readScene(o.out / "scene.json");
  EXPECT_EQ(scene.resolution, fine);
  EXPECT_DOUBLE_EQ(scene.render.absorption, sim::readScene(simulated() / "scene.json").render.absorption / 2);
  for (int t = 0; t < 5; ++t) {
    const std::vector<float> f = field(o.out, "density", t), c = field(simulated(), "density", t);
    // 8 fine cells per coarse cell; the centre of mass at the same place of the box.
    EXPECT_NEAR(sum(f) / 8, sum(c), 0.02 * sum(c)) << "frame " << t;
    const Vec3 fineCentre = centreOfMass(f, fine) / 2.0, coarseCentre = centreOfMass(c, coarse);
    EXPECT_NEAR(fineCentre[1], coarseCentre[1], 0.15) << "frame " << t;
    EXPECT_NEAR(fineCentre[0], coarseCentre[0], 0.15) << "frame " << t;
  }
}

TEST_F(ResimTest, FramesPastTheVideoAreFedWithTheMeanInflowAndKeepRising) {
  resim::ResimOptions o = quick(tinyScratch("longer"));
  o.frames = kFrames + 4;
  o.inflowScale = 0.5;
  resim::runResimulation(context(), o);
  // Frames 1 .. 7 of the reconstruction hold inflow; the mean of the last (up to 8) of them, times the scale.
  const GridSize grid{.x = 16, .y = 28, .z = 16};
  std::vector<double> mean(static_cast<std::size_t>(grid.cells()), 0.0);
  for (int t = 1; t < kFrames; ++t) {
    const std::vector<float> inflow = field(simulated(), "inflow", t);
    for (std::size_t i = 0; i < mean.size(); ++i) mean[i] += 0.5 * inflow[i] / (kFrames - 1);
  }
  for (int t = kFrames; t < kFrames + 4; ++t) {
    const std::vector<float> inflow = field(o.out, "inflow", t);
    for (std::size_t i = 0; i < mean.size(); ++i) ASSERT_NEAR(inflow[i], mean[i], 1e-6) << "frame " << t << ", cell " << i;
  }
  EXPECT_EQ(field(o.out, "inflow", 3), [&] {
    std::vector<float> half = field(simulated(), "inflow", 3);
    for (float& v : half) v *= 0.5f;
    return half;
  }());
  const double last = centreOfMass(field(o.out, "density", kFrames - 1), grid)[1];
  const double later = centreOfMass(field(o.out, "density", kFrames + 3), grid)[1];
  EXPECT_GT(later, last + 0.3) << "the reconstruction's force keeps driving the plume";
}

TEST_F(ResimTest, ForcesPushTheSmokeFromTheirFirstFrame) {
  const GridSize grid{.x = 16, .y = 28, .z = 16};
  const fs::path folder = tinyScratch("forces");
  // A swirl about the vertical axis through the box's centre: f = s (-(z - 8), 0, x - 8).
  std::vector<float> swirl(static_cast<std::size_t>(3 * grid.cells()), 0.0f);
  for (std::size_t c = 0; c < swirl.size() / 3; ++c) {
    const double x = static_cast<double>(static_cast<int64_t>(c) % grid.x) + 0.5,
                 z = static_cast<double>(static_cast<int64_t>(c) / (grid.x * grid.y)) + 0.5;
    swirl[3 * c] = static_cast<float>(-0.01 * (z - 8));
    swirl[3 * c + 2] = static_cast<float>(0.01 * (x - 8));
  }
  io::writeNpz(folder / "swirl.npz", {{"force", io::NpyArray::fromFloats({16, 28, 16, 3}, swirl)}});
  resim::ResimOptions wind = quick(folder / "wind"), turn = quick(folder / "turn"), none = quick(folder / "none");
  wind.forces = {resim::parseForce("uniform:0.1,0,0@2:6")};
  turn.forces = {resim::parseForce((folder / "swirl.npz").string() + "@2")};
  for (const resim::ResimOptions* o : {&wind, &turn, &none}) resim::runResimulation(context(), *o);
  EXPECT_EQ(field(wind.out, "density", 2), field(none.out, "density", 2)) << "the force starts at frame 2";
  const double pushed = centreOfMass(field(wind.out, "density", kFrames - 1), grid)[0];
  const double still = centreOfMass(field(none.out, "density", kFrames - 1), grid)[0];
  EXPECT_GT(pushed, still + 0.1);
  // The swirl turns the flow its way: the velocity's projection on the swirl grows from about 0.
  auto alongSwirl = [&](const fs::path& run) {
    const std::vector<float> u = field(run, "velocity", kFrames - 1);
    double dot = 0;
    for (std::size_t i = 0; i < u.size(); ++i) dot += static_cast<double>(u[i]) * swirl[i];
    return dot;
  };
  EXPECT_GT(alongSwirl(turn.out), alongSwirl(none.out) + 0.1);
  EXPECT_TRUE(fs::exists(turn.out / "forces" / "force_00.npz"));
  EXPECT_EQ(sim::readScene(turn.out / "scene.json").forceFields.size(), 1u);
}

TEST_F(ResimTest, BadInputsAreErrorsThatTouchNothing) {
  const fs::path root = tinyScratch("bad");
  auto message = [&](const resim::ResimOptions& o) {
    try {
      resim::runResimulation(context(), o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  resim::ResimOptions o = quick(root / "out");
  o.obstacles = {resim::parseObstacle("sphere:30,9,8,2")};
  EXPECT_NE(message(o).find("--obstacle sphere:30,9,8,2: the centre lies outside the reconstruction's box [0, 16] x [0, 28] x [0, 16]"),
            std::string::npos) << message(o);
  o.obstacles = {resim::parseObstacle("sphere:8,9,8,2@9")};
  EXPECT_NE(message(o).find("starts at frame 9, but the re-simulation has frames 0..7"), std::string::npos) << message(o);
  o.obstacles = {resim::parseObstacle("sphere:0,0,0,0.2")};
  EXPECT_NE(message(o).find("covers no cell"), std::string::npos) << message(o);
  o.obstacles.clear();
  o.forces = {resim::parseForce((root / "missing.npz").string())};
  EXPECT_NE(message(o).find("no such file"), std::string::npos) << message(o);
  o.forces.clear();
  EXPECT_FALSE(fs::exists(root / "out")) << "nothing is written before the inputs are checked";

  resim::ResimOptions notRecon = quick(root / "out2", root);
  EXPECT_NE(message(notRecon).find("not a run folder"), std::string::npos) << message(notRecon);
  const fs::path simulation = root / "simulation";
  sim::Scene scene = sim::randomScene(3, {.x = 8, .y = 12, .z = 8}, 1);
  scene.render.enabled = false;
  sim::runScene(context(), scene, simulation, {});
  notRecon.source = simulation;
  EXPECT_NE(message(notRecon).find("not a reconstruction (its run.json was written by smokesvd simulate)"), std::string::npos)
      << message(notRecon);

  fs::create_directories(root / "busy");
  std::ofstream(root / "busy" / "notes.txt") << "keep me";
  resim::ResimOptions busy = quick(root / "busy");
  busy.overwrite = true;
  EXPECT_NE(message(busy).find("is not empty and holds no re-simulation"), std::string::npos) << message(busy);
  EXPECT_TRUE(fs::exists(root / "busy" / "notes.txt"));
  std::ofstream(root / "file") << "a file";
  EXPECT_NE(message(quick(root / "file" / "out")).find("cannot create the output folder"), std::string::npos);

  for (const char* bad : {"cube:1,2,3,4", "sphere:1,2,3", "sphere:1,2,3,-1", "sphere:1,2,3,4@x", "sphere:1,2,3,4@5:2"})
    EXPECT_THROW(resim::parseObstacle(bad), Error) << bad;
  for (const char* bad : {"uniform:1,2", "force.txt", "uniform:1,2,3@-1"}) EXPECT_THROW(resim::parseForce(bad), Error) << bad;
}

}  // namespace
}  // namespace smokesvd::testing

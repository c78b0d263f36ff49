#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "nets/io/npy.h"
#include "pipeline/physics/advection.h"
#include "pipeline/sim/domain.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "pipeline/sim/simulator.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/temp_dir.h"
#include "tests/pipeline/physics/sim_reference.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

// A fresh folder `name` inside this program's TempDir (removed when the program ends).
fs::path scratchDirectory(const std::string& name) {
  static const TempDir root("simulator");
  const fs::path path = root / name;
  fs::remove_all(path);
  fs::create_directories(path);
  return path;
}

// A small plume that exercises every feature: heat, wind, vorticity, an obstacle that appears, a source
// that sets the velocity and one that adds density, noise, an open top.
sim::Scene plumeScene(int frames) {
  sim::Scene scene;
  scene.resolution = {.x = 15, .y = 25, .z = 13};
  scene.frames = frames;
  scene.densityBuoyancy = 0.02;
  scene.temperatureBuoyancy = 0.01;
  scene.wind.points = {{0, {0.004, 0, 0}}, {6, {-0.004, 0, 0.002}}};
  scene.vorticity = 0.1;
  sim::Source sphere;
  sphere.shape.centre = {7.5, 3.5, 6.5};
  sphere.shape.size = {2.5, 0, 0};
  sphere.temperature = sim::Keyframes<double>::constant(0.8);
  sphere.noise = {0.4, 2.0, {0, 0.5, 0}, 77};
  sphere.velocity = sim::Keyframes<Vec3>::constant({0, 0.3, 0});
  sim::Source box;
  box.shape.kind = physics::SourceShape::Box;
  box.shape.centre = {4, 4, 4};
  box.shape.size = {1.5, 1.5, 1.5};
  box.mode = physics::InflowMode::Add;
  box.density.points = {{0, 0.2}, {4, 0.6}};
  scene.sources = {sphere, box};
  sim::Obstacle ball;
  ball.shape.centre = {7.5, 15, 6.5};
  ball.shape.size = {2.2, 0, 0};
  ball.frames = {2, -1};
  scene.obstacles.push_back(ball);
  scene.render.views = 4;
  scene.render.width = 15;
  scene.render.height = 25;
  return scene;
}

std::string fileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// Every regular file under `directory` by relative path: its bytes, or for .npz files the arrays
// (zip members carry their write time, which differs between runs).
std::map<std::string, std::string> directoryContents(const fs::path& directory) {
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(directory)) {
    if (!entry.is_regular_file()) continue;
    std::string content;
    if (entry.path().extension() == ".npz") {
      for (const auto& [key, array] : io::readNpz(entry.path())) {
        const std::vector<std::byte> bytes = io::serializeNpy(array);
        content += key + ":" + std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size());
      }
    } else {
      content = fileBytes(entry.path());
    }
    files[fs::relative(entry.path(), directory).string()] = content;
  }
  return files;
}

// Names of the files that are missing from one side or differ.
std::vector<std::string> differences(const fs::path& a, const fs::path& b) {
  const auto filesA = directoryContents(a), filesB = directoryContents(b);
  std::vector<std::string> names;
  for (const auto& [name, content] : filesA)
    if (!filesB.count(name) || filesB.at(name) != content) names.push_back(name);
  for (const auto& [name, content] : filesB)
    if (!filesA.count(name)) names.push_back(name);
  return names;
}

class SimulatorTest : public GpuTest {};

TEST_F(SimulatorTest, SavedFramesObeyTheAdvectionRelation) {
  const sim::Scene scene = plumeScene(5);
  sim::Simulator simulator(context(), scene);
  for (int f = 0; f < 3; ++f) simulator.advanceFrame();
  const std::vector<float> density = simulator.density().download(), velocity = simulator.velocity().download();
  simulator.advanceFrame();
  // density[3] = A(density[2], velocity[2]) + inflow[3], with the flags of frame 3.
  Tensor flags = Tensor::fromHost(context(), simulator.grid().volume(), sim::sceneFlags(scene, 3));
  Tensor d = Tensor::fromHost(context(), simulator.grid().volume(), density);
  Tensor u = Tensor::fromHost(context(), simulator.grid().vector(), velocity);
  Tensor expected(context(), simulator.grid().volume());
  Stream stream(context());
  const physics::FlagGrid flagGrid(stream, flags);
  physics::advect(stream, flagGrid, d, u, &simulator.inflow(), {scene.advection, 1.0f, 1.0f}, expected);
  stream.submit();
  EXPECT_TRUE(allClose(simulator.density(), expected.download(), {0, 0}));
}

TEST_F(SimulatorTest, AnObstacleThatAppearsInTheSmokeHoldsNoDensity) {
  sim::Scene scene = plumeScene(7);
  scene.obstacles[0].shape.centre = {7.5, 6.5, 6.5};  // just above the sphere source, inside its plume
  scene.obstacles[0].frames = {3, -1};
  const std::vector<float> flags = sim::sceneFlags(scene, 3), before = sim::sceneFlags(scene, 0);
  sim::Simulator simulator(context(), scene);
  for (int f = 0; f < scene.frames; ++f) {
    simulator.advanceFrame();
    const std::vector<float> density = simulator.density().download();
    double inside = 0;
    for (std::size_t i = 0; i < flags.size(); ++i)
      if (flags[i] != before[i]) inside += density[i];
    if (f == 2) {
      EXPECT_GT(inside, 0.1) << "the smoke should fill the obstacle's place before it appears";
    } else if (f >= 3) {
      EXPECT_EQ(inside, 0.0) << "frame " << f;
    }
  }
}

TEST_F(SimulatorTest, APlumeRisesAndStaysDivergenceFree) {
  const sim::Scene scene = plumeScene(10);
  sim::Simulator simulator(context(), scene);
  const GridSize grid = simulator.grid();
  double previousHeight = 0, firstHeight = 0;
  for (int f = 0; f < scene.frames; ++f) {
    const sim::FrameReport report = simulator.advanceFrame();
    EXPECT_TRUE(report.converged) << "frame " << f;
    const std::vector<float> density = simulator.density().download();
    double mass = 0, height = 0;
    for (std::size_t i = 0; i < density.size(); ++i) {
      ASSERT_TRUE(std::isfinite(density[i]));
      ASSERT_GE(density[i], 0.0f);
      mass += density[i];
      height += density[i] * static_cast<double>((static_cast<int64_t>(i) / grid.x) % grid.y);
    }
    height /= mass;
    if (f == 0) firstHeight = height;
    if (f >= 4) {
      EXPECT_GT(height, previousHeight) << "the smoke's centre of mass should rise, frame " << f;
    }
    previousHeight = height;
    // max |div u| after the projection, from the saved velocity.
    const std::vector<float> flags = sim::sceneFlags(scene, f);
    const double divergence =
        ref::maxAbs(ref::divergence(ref::FlagView(grid, flags), ref::widen(simulator.velocity().download())));
    EXPECT_LE(divergence, std::max(scene.pressureTolerance * 10, 1e-5)) << "frame " << f;
  }
  EXPECT_GT(previousHeight, firstHeight + 0.5);
}

TEST_F(SimulatorTest, RunsAreDeterministic) {
  const sim::Scene scene = plumeScene(3);
  const fs::path a = scratchDirectory("deterministic_a"), b = scratchDirectory("deterministic_b");
  sim::runScene(context(), scene, a, {});
  sim::runScene(context(), scene, b, {});
  EXPECT_TRUE(fs::exists(a / "renders" / "view_03" / "0002.png"));
  EXPECT_TRUE(fs::exists(a / "fields" / "temperature_0002.npz"));
  EXPECT_TRUE(fs::exists(a / "run.json"));
  EXPECT_FALSE(fs::exists(a / "checkpoint.npz"));
  EXPECT_EQ(differences(a, b), std::vector<std::string>{});
}

TEST_F(SimulatorTest, ARandomSceneRendersTheSamePlumeForTheSameSeed) {
  const fs::path a = scratchDirectory("seed_a"), b = scratchDirectory("seed_b");
  for (const fs::path& directory : {a, b}) {
    sim::Scene scene = sim::randomScene(5, {.x = 16, .y = 28, .z = 16}, 4);
    scene.render.views = 4;
    sim::runScene(context(), scene, directory, {});
  }
  for (int v = 0; v < 4; ++v) {
    const fs::path view = fs::path("renders") / ("view_0" + std::to_string(v)) / "0003.png";
    ASSERT_TRUE(fs::exists(a / view)) << view;
    EXPECT_EQ(fileBytes(a / view), fileBytes(b / view)) << view;
  }
}

TEST_F(SimulatorTest, AnInterruptedRunResumesToIdenticalOutput) {
  const sim::Scene scene = plumeScene(5);
  const fs::path whole = scratchDirectory("whole"), pieces = scratchDirectory("pieces");
  sim::runScene(context(), scene, whole, {});

  sim::RunOptions stopEarly;
  stopEarly.maxFrames = 3;
  const sim::RunResult first = sim::runScene(context(), scene, pieces, stopEarly);
  EXPECT_FALSE(first.complete);
  EXPECT_TRUE(fs::exists(pieces / "checkpoint.npz"));
  // What a kill in the middle of the next frame leaves behind: a temporary file, never a final name.
  std::ofstream(pieces / "fields" / "density_0003.npz.tmp") << "truncated";
  const sim::RunResult second = sim::runScene(context(), scene, pieces, {});
  EXPECT_TRUE(second.resumed);
  EXPECT_TRUE(second.complete);
  EXPECT_EQ(second.framesSimulated, 2);
  fs::remove(pieces / "fields" / "density_0003.npz.tmp");
  EXPECT_EQ(differences(whole, pieces), std::vector<std::string>{});

  const sim::RunResult third = sim::runScene(context(), scene, pieces, {});
  EXPECT_EQ(third.framesSimulated, 0);
  EXPECT_TRUE(third.complete);
}

TEST_F(SimulatorTest, ADirectoryWithAnotherSceneIsAnError) {
  const fs::path directory = scratchDirectory("other_scene");
  sim::RunOptions quick;
  quick.render = false;
  sim::runScene(context(), plumeScene(1), directory, quick);
  sim::Scene other = plumeScene(1);
  other.vorticity = 0.3;
  EXPECT_THROW(sim::runScene(context(), other, directory, quick), Error);
  quick.overwrite = true;
  EXPECT_TRUE(sim::runScene(context(), other, directory, quick).complete);
}

TEST_F(SimulatorTest, FieldFilesHaveTheDocumentedLayout) {
  const sim::Scene scene = plumeScene(1);
  const fs::path directory = scratchDirectory("layout");
  sim::RunOptions options;
  options.render = false;
  sim::runScene(context(), scene, directory, options);
  const Shape volume{13, 25, 15};
  EXPECT_EQ(io::readNpzMember(directory / "fields" / "density_0000.npz", "density").shape, volume);
  EXPECT_EQ(io::readNpzMember(directory / "fields" / "inflow_0000.npz", "inflow").shape, volume);
  EXPECT_EQ(io::readNpzMember(directory / "fields" / "velocity_0000.npz", "velocity").shape, (Shape{13, 25, 15, 3}));
  const io::NpyArray flags = io::readNpzMember(directory / "flags.npz", "flags");
  EXPECT_EQ(flags.dtype, io::DType::Int32);
  EXPECT_EQ(flags.shape, volume);
}

}  // namespace
}  // namespace smokesvd::testing

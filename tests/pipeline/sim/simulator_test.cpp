#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "pipeline/physics/advection.h"
#include "pipeline/sim/domain.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "pipeline/sim/run_files.h"
#include "pipeline/sim/simulator.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/pipeline/physics/sim_reference.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

// A fresh folder `name` inside this program's temporary folder (removed when the program ends).
fs::path scratchDirectory(const std::string& name) {
  static const io::TemporaryFolder root("simulator");
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
// (zip members carry their write time, which differs between runs), or for the manifest its sorted
// lines (the order files were first written in depends on where a run was interrupted).
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
    } else if (entry.path().filename() == sim::RunFiles::kManifest) {
      std::ifstream manifest(entry.path());
      std::set<std::string> lines;
      for (std::string line; std::getline(manifest, line);) lines.insert(line);
      for (const std::string& line : lines) content += line + "\n";
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
  EXPECT_TRUE(fs::exists(a / "checkpoint.npz")) << "kept, so that the run can be extended";
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
  // What a kill in the middle of a write leaves behind (without a signal handler): a temporary file,
  // never a final name. The resumed run removes them.
  std::ofstream(pieces / "fields" / "density_0002.npz.tmp") << "truncated";
  std::ofstream(pieces / "renders" / "view_01" / "0002.png.tmp") << "truncated";
  std::ofstream(pieces / "checkpoint.npz.tmp") << "truncated";
  const sim::RunResult second = sim::runScene(context(), scene, pieces, {});
  EXPECT_TRUE(second.resumed);
  EXPECT_TRUE(second.complete);
  EXPECT_EQ(second.framesSimulated, 2);
  for (const char* temporary : {"fields/density_0002.npz.tmp", "renders/view_01/0002.png.tmp", "checkpoint.npz.tmp"})
    EXPECT_FALSE(fs::exists(pieces / temporary)) << temporary;
  EXPECT_EQ(differences(whole, pieces), std::vector<std::string>{});

  const sim::RunResult third = sim::runScene(context(), scene, pieces, {});
  EXPECT_EQ(third.framesSimulated, 0);
  EXPECT_TRUE(third.complete);
}

TEST_F(SimulatorTest, AFinishedRunIsExtendedWithMoreFrames) {
  const fs::path whole = scratchDirectory("extend_whole"), extended = scratchDirectory("extend");
  sim::runScene(context(), plumeScene(5), whole, {});
  ASSERT_TRUE(sim::runScene(context(), plumeScene(3), extended, {}).complete);
  const sim::RunResult more = sim::runScene(context(), plumeScene(5), extended, {});
  EXPECT_TRUE(more.resumed);
  EXPECT_TRUE(more.complete);
  EXPECT_EQ(more.framesSimulated, 2);
  EXPECT_EQ(differences(whole, extended), std::vector<std::string>{});
  // Fewer frames than the run holds: nothing to do, nothing deleted.
  EXPECT_EQ(sim::runScene(context(), plumeScene(2), extended, {}).framesSimulated, 0);
  EXPECT_TRUE(fs::exists(extended / "fields" / "density_0004.npz"));
}

// --overwrite deletes what runs of smokesvd wrote (their manifest) and nothing else.
TEST_F(SimulatorTest, OverwriteDeletesOnlyTheFilesARunWrote) {
  const fs::path directory = scratchDirectory("overwrite_own");
  sim::RunOptions options;
  options.render = true;
  sim::runScene(context(), plumeScene(3), directory, options);
  std::ofstream(directory / "notes.txt") << "mine";
  std::ofstream(directory / "fields" / "my_density.npz") << "mine";
  std::ofstream(directory / "renders" / "view_00" / "keep.png") << "mine";
  options.overwrite = true;
  sim::Scene other = plumeScene(1);
  other.render.views = 2;
  EXPECT_TRUE(sim::runScene(context(), other, directory, options).complete);
  for (const char* mine : {"notes.txt", "fields/my_density.npz", "renders/view_00/keep.png"})
    EXPECT_TRUE(fs::exists(directory / mine)) << mine;
  // The old run's files beyond the new one's are gone, and so are the folders they alone filled.
  EXPECT_FALSE(fs::exists(directory / "fields" / "density_0002.npz"));
  EXPECT_FALSE(fs::exists(directory / "renders" / "view_03"));
  EXPECT_TRUE(fs::exists(directory / "renders" / "view_01" / "0000.png"));
  EXPECT_EQ(sim::readScene(directory / "scene.json"), other);
}

TEST_F(SimulatorTest, OverwriteRefusesAFolderThatIsNotARun) {
  const fs::path home = scratchDirectory("not_a_run");
  fs::create_directories(home / "renders");
  std::ofstream(home / "renders" / "holiday.png") << "mine";
  std::ofstream(home / "fields") << "mine";
  sim::RunOptions options;
  options.render = false;
  options.overwrite = true;
  try {
    sim::runScene(context(), plumeScene(1), home, options);
    ADD_FAILURE() << "overwrote a folder that is not a run";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("is not a run of smokesvd simulate"), std::string::npos) << error.what();
  }
  // Without --overwrite a run does not start among files of its own names either.
  options.overwrite = false;
  try {
    sim::runScene(context(), plumeScene(1), home, options);
    ADD_FAILURE() << "started a run among someone else's files";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("holds fields but no manifest.txt"), std::string::npos) << error.what();
  }
  EXPECT_TRUE(fs::exists(home / "renders" / "holiday.png"));
  EXPECT_TRUE(fs::is_regular_file(home / "fields"));
  // An empty folder, or none, is fine to overwrite.
  EXPECT_TRUE(sim::runScene(context(), plumeScene(1), scratchDirectory("empty"), {.render = false, .overwrite = true}).complete);
}

TEST_F(SimulatorTest, ACorruptCheckpointSaysWhatToDo) {
  const fs::path directory = scratchDirectory("corrupt_checkpoint");
  sim::RunOptions stopEarly;
  stopEarly.render = false;
  stopEarly.maxFrames = 1;
  sim::runScene(context(), plumeScene(3), directory, stopEarly);
  std::ofstream(directory / "checkpoint.npz", std::ios::trunc) << "not a zip";
  try {
    sim::runScene(context(), plumeScene(3), directory, stopEarly);
    ADD_FAILURE() << "resumed from a corrupt checkpoint";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("checkpoint.npz"), std::string::npos) << message;
    EXPECT_NE(message.find("delete"), std::string::npos) << message;
    EXPECT_NE(message.find("--overwrite"), std::string::npos) << message;
  }
}

// A state that becomes NaN or infinite stops the run, naming the frame and the field, and writes nothing
// of that frame.
TEST_F(SimulatorTest, ANonFiniteStateStopsTheRunNamingFrameAndField) {
  const sim::Scene scene = plumeScene(3);
  const std::size_t cells = static_cast<std::size_t>(scene.resolution.cells());
  sim::SimulatorState state;
  state.frame = 1;
  state.density.assign(cells, 0.0f);
  state.velocity.assign(3 * cells, 0.0f);
  state.pressure.assign(cells, 0.0f);
  state.temperature.assign(cells, 0.0f);
  {
    sim::Simulator simulator(context(), scene);
    sim::SimulatorState bad = state;
    bad.velocity[cells + 7 * 15 * 25 + 12 * 15 + 7] = std::numeric_limits<float>::infinity();
    simulator.restore(bad);
    try {
      simulator.advanceFrame();
      ADD_FAILURE() << "an infinite velocity went unnoticed";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("frame 1, step 0: the velocity became NaN or infinite"), std::string::npos)
          << error.what();
    }
  }
  const fs::path directory = scratchDirectory("non_finite");
  sim::Simulator simulator(context(), scene);
  sim::SimulatorState bad = state;
  bad.density[7 * 15 * 25 + 12 * 15 + 7] = std::nanf("");
  simulator.restore(bad);  // as if frame 0 had ended with it (a NaN density reaches the velocity next)
  sim::RunFiles files(directory);
  try {
    sim::writeFrameFields(files, simulator);
    ADD_FAILURE() << "a NaN density was written";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("frame 0: density: element [7, 12, 7] of [13, 25, 15] is nan"),
              std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(fs::exists(directory / "fields" / "density_0000.npz"));
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

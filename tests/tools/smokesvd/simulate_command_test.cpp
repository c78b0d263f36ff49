#include <gtest/gtest.h>

#include <filesystem>
#include <csignal>
#include <fstream>

#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "pipeline/sim/scene.h"
#include "tests/harness/command.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

// A fresh folder `name` inside this program's temporary folder (removed when the program ends).
fs::path scratchDirectory(const std::string& name) {
  static const io::TemporaryFolder root("simulate-cli");
  const fs::path path = root / name;
  fs::remove_all(path);
  fs::create_directories(path);
  return path;
}

// A two-frame scene file of 8 x 12 x 8 cells; returns its path.
std::string writeTinyScene(const fs::path& path) {
  std::ofstream(path) << R"({"resolution": [8, 12, 8], "frames": 2, "render": {"views": 2}})";
  return path.string();
}

TEST(SimulateCli, RandomScenesWriteFieldsRendersAndTheirScene) {
  const fs::path out = scratchDirectory("random");
  const CommandResult result =
      runSmokesvd("simulate --scenes 2 --seed 9 --preset tiny --frames 2 --out " + out.string());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  for (const char* scene : {"scene_0000", "scene_0001"}) {
    EXPECT_TRUE(fs::exists(out / scene / "fields" / "density_0001.npz"));
    EXPECT_TRUE(fs::exists(out / scene / "fields" / "velocity_0001.npz"));
    EXPECT_TRUE(fs::exists(out / scene / "fields" / "inflow_0001.npz"));
    EXPECT_TRUE(fs::exists(out / scene / "renders" / "view_15" / "0001.png"));
  }
  const sim::Scene first = sim::readScene(out / "scene_0000" / "scene.json");
  EXPECT_EQ(first.seed, 9u);
  EXPECT_EQ(first.frames, 2);
  EXPECT_EQ(first.resolution, (GridSize{.x = 16, .y = 28, .z = 16}));
  EXPECT_EQ(sim::readScene(out / "scene_0001" / "scene.json").seed, 10u);
  EXPECT_NE(result.err.find("frames/s"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("ETA"), std::string::npos) << result.err;

  // The same command again finds the runs complete.
  const CommandResult again = runSmokesvd("simulate --scenes 2 --seed 9 --preset tiny --frames 2 --out " + out.string());
  ASSERT_EQ(again.exitCode, 0) << again.err;
  EXPECT_NE(again.err.find("already complete"), std::string::npos) << again.err;
}

TEST(SimulateCli, ASavedSceneReproducesItsRun) {
  const fs::path out = scratchDirectory("reproduce");
  ASSERT_EQ(runSmokesvd("simulate --scenes 1 --seed 4 --preset tiny --frames 2 --no-render --out " + (out / "a").string())
                .exitCode,
            0);
  const CommandResult rerun = runSmokesvd("simulate --scene " + (out / "a" / "scene_0000" / "scene.json").string() +
                                          " --no-render --out " + (out / "b").string());
  ASSERT_EQ(rerun.exitCode, 0) << rerun.err;
  for (const auto& [file, key] : {std::pair{"fields/density_0001.npz", "density"}, {"fields/velocity_0001.npz", "velocity"}}) {
    const io::NpyArray a = io::readNpzMember(out / "a" / "scene_0000" / file, key);
    const io::NpyArray b = io::readNpzMember(out / "b" / file, key);
    EXPECT_EQ(a.shape, b.shape) << file;
    EXPECT_EQ(a.floats, b.floats) << file;
  }
  EXPECT_EQ(sim::readScene(out / "a" / "scene_0000" / "scene.json"), sim::readScene(out / "b" / "scene.json"));
}

TEST(SimulateCli, BadSceneIsAOneLineErrorNamingFileAndField) {
  const fs::path out = scratchDirectory("bad");
  std::ofstream(out / "scene.json") << R"({"resolution": [8, 12, 10], "frames": 2, "vorticity": "strong"})";
  const CommandResult result = runSmokesvd("simulate --scene " + (out / "scene.json").string() + " --out " + (out / "run").string());
  EXPECT_NE(result.exitCode, 0);
  EXPECT_EQ(countLines(result.err), 1) << result.err;
  EXPECT_NE(result.err.find("scene.json: field 'vorticity': expected a number in"), std::string::npos) << result.err;
}

TEST(SimulateCli, ConflictingOptionsAreErrors) {
  const fs::path out = scratchDirectory("conflict");
  std::ofstream(out / "scene.json") << R"({"resolution": [8, 12, 10], "frames": 2})";
  EXPECT_NE(runSmokesvd("simulate --out " + out.string()).exitCode, 0);
  const CommandResult both = runSmokesvd("simulate --scene " + (out / "scene.json").string() +
                                         " --resolution 8,8,8 --out " + out.string());
  EXPECT_NE(both.exitCode, 0);
  EXPECT_NE(both.err.find("--resolution"), std::string::npos) << both.err;
}

// --overwrite never deletes what a run did not write: `--out ~ --overwrite` must not wipe ~/renders.
TEST(SimulateCli, OverwriteRefusesAFolderThatIsNotARun) {
  const fs::path home = scratchDirectory("home");
  fs::create_directories(home / "renders" / "holiday");
  std::ofstream(home / "renders" / "holiday" / "beach.png") << "mine";
  const CommandResult result = runSmokesvd("simulate --scene " + writeTinyScene(home / "../home-scene.json") +
                                           " --no-render --overwrite --out " + home.string());
  EXPECT_EQ(result.exitCode, 1);
  EXPECT_EQ(countLines(result.err), 1) << result.err;
  EXPECT_NE(result.err.find("is not a run of smokesvd simulate"), std::string::npos) << result.err;
  EXPECT_TRUE(fs::exists(home / "renders" / "holiday" / "beach.png"));
}

TEST(SimulateCli, AFinishedRunIsExtendedWithMoreFrames) {
  const fs::path out = scratchDirectory("extend");
  ASSERT_EQ(runSmokesvd("simulate --scene " + writeTinyScene(out / "../extend-scene.json") + " --no-render --out " +
                        out.string()).exitCode,
            0);
  ASSERT_FALSE(fs::exists(out / "fields" / "density_0002.npz"));
  const CommandResult more = runSmokesvd("simulate --scene " + (out / "scene.json").string() + " --frames 3 --no-render --out " +
                                         out.string());
  ASSERT_EQ(more.exitCode, 0) << more.err;
  EXPECT_NE(more.err.find("resumed, 1 frames simulated"), std::string::npos) << more.err;
  EXPECT_TRUE(fs::exists(out / "fields" / "density_0002.npz"));
  EXPECT_EQ(sim::readScene(out / "scene.json").frames, 3);
}

// Ctrl-C in the middle of a run: whenever it lands, no temporary file is left, and the run resumes.
TEST(SimulateCli, AnInterruptLeavesNoTemporaryFiles) {
  const fs::path out = scratchDirectory("interrupt");
  const std::string arguments = "simulate --scenes 1 --seed 3 --preset tiny --frames 400 --out " + out.string();
  const CommandResult interrupted = runSmokesvd(arguments, "timeout --preserve-status -s INT 4");
  EXPECT_EQ(interrupted.exitCode, 128 + SIGINT) << interrupted.err;
  std::vector<std::string> temporaries;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(out))
    if (entry.path().string().find(".tmp") != std::string::npos) temporaries.push_back(entry.path().string());
  EXPECT_EQ(temporaries, std::vector<std::string>{});
}

}  // namespace
}  // namespace smokesvd::testing

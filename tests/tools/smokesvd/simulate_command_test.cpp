#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "nets/io/npy.h"
#include "pipeline/sim/scene.h"
#include "tests/harness/command.h"
#include "tests/harness/temp_dir.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

// A fresh folder `name` inside this program's TempDir (removed when the program ends).
fs::path scratchDirectory(const std::string& name) {
  static const TempDir root("simulate-cli");
  const fs::path path = root / name;
  fs::remove_all(path);
  fs::create_directories(path);
  return path;
}

int countLines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

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

}  // namespace
}  // namespace smokesvd::testing

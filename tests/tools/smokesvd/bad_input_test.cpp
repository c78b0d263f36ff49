// Bad input as a new user gives it, on the command line: every case is one `smokesvd: error:` line that
// names the file or flag and what was expected, a non-zero exit status (2: the command line was not
// understood, 1: running it failed), and it comes in bounded time, before anything large is allocated.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "tests/harness/command.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kFailed = 1, kBadCommandLine = 2;

struct BadInput {
  std::string arguments;
  std::string message;  // a part of the error line
  int exitCode = kFailed;
  std::string environment = "";
};

void expectOneLineError(const BadInput& c) {
  const auto start = std::chrono::steady_clock::now();
  const CommandResult result = runSmokesvd(c.arguments, c.environment);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(result.exitCode, c.exitCode) << c.arguments << "\n" << result.err;
  EXPECT_EQ(countLines(result.err), 1) << c.arguments << "\n" << result.err;
  EXPECT_EQ(result.err.rfind("smokesvd: error: ", 0), 0u) << c.arguments << "\n" << result.err;
  EXPECT_NE(result.err.find(c.message), std::string::npos) << c.arguments << "\nexpected: " << c.message << "\n"
                                                           << result.err;
  EXPECT_LT(seconds, 60) << c.arguments;  // a failure is found before any long work
}

class BadInputTest : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return folder_.file(name); }
  // A one-camera calibration file (no video needed until a frame is decoded).
  std::string calibration() const {
    const std::string file = path("info.json");
    std::ofstream(file) << R"({"train_videos": [{"file_name": "a.mp4", "camera_hw": [20, 10], "camera_angle_x": 0.5,
        "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}],
        "voxel_scale": [1, 1, 1], "voxel_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]})";
    return file;
  }
  std::string volume(const std::string& name, float value = 0.5f) const {
    const std::string file = path(name);
    std::vector<float> values(4 * 5 * 6, 0.5f);
    values[37] = value;
    io::writeNpy(file, io::NpyArray::fromFloats({4, 5, 6}, values));
    return file;
  }
  std::string scene(const std::string& name, const std::string& extra) const {
    const std::string file = path(name);
    std::ofstream(file) << R"({"resolution": [8, 12, 8], "frames": 2)" << extra << "}";
    return file;
  }
  io::TemporaryFolder folder_{"bad-input"};
};

TEST_F(BadInputTest, CommandLineErrorsAreOneLineWithExitStatus2) {
  const std::string v = volume("v.npy");
  for (const BadInput& c : std::vector<BadInput>{
           {"render " + v + " --width 0 --out " + path("o"), "--width: expected a whole number from 1 to 8192, got '0'",
            kBadCommandLine},
           {"render " + v + " --width abc --out " + path("o"), "--width: expected a whole number", kBadCommandLine},
           {"render " + v + " --fps nan --mp4 --out " + path("o"), "--fps: expected a number above 0", kBadCommandLine},
           {"render " + v + " --gain nan --out " + path("o"), "--gain: expected a number from 0", kBadCommandLine},
           {"render " + v + " --views 3 --angles 0,90 --out " + path("o"), "--views excludes --angles", kBadCommandLine},
           {"render " + v + " --camera a.mp4 --out " + path("o"), "--camera requires --cameras", kBadCommandLine},
           {"render " + v + " --fps 30 --out " + path("o"), "--fps requires --mp4", kBadCommandLine},
           {"render " + v + " --light-step 2 --out " + path("o"), "--light-step requires --light", kBadCommandLine},
           {"render " + v + " --bits 5 --out " + path("o"), "--bits", kBadCommandLine},
           {"simulate --scenes 2 --seed -1 --preset tiny --out " + path("s"), "--seed: expected a whole number from 0",
            kBadCommandLine},
           {"simulate --scenes 1000000000 --preset tiny --frames 1 --out " + path("s"),
            "--scenes: expected a whole number from 1 to 100000", kBadCommandLine},
           {"simulate --scenes 1 --frames 2000000 --out " + path("s"), "--frames: expected a whole number from 1 to 1000000",
            kBadCommandLine},
           {"simulate --scenes 1 --resolution 8,2000,8 --out " + path("s"), "--resolution: expected a whole number from 3 to 1024",
            kBadCommandLine},
           {"simulate --scenes 1", "--out is required", kBadCommandLine},
           {"bench --runs 0", "--runs: expected a whole number from 1", kBadCommandLine},
           {"--bogus info", "--bogus", kBadCommandLine},
           {"info extra", "extra", kBadCommandLine},
           {"", "A subcommand is required", kBadCommandLine},
           {"evaluate --help", "unknown command 'evaluate'; the commands are ", kBadCommandLine},
           {"eval r --truth t --cameras c.json --videos v --out o", "--truth excludes --cameras", kBadCommandLine},
           {"eval r --out o", "give either --truth SCENE_DIR or --cameras info.json with --videos DIR", kBadCommandLine},
           {"eval r --cameras c.json --out o", "--cameras requires --videos", kBadCommandLine},
           {"eval r --cameras c.json --videos v --region frame --width 100000 --out o",
            "--width: expected a whole number from 1 to 8192", kBadCommandLine},
           {"eval r --cameras c.json --videos v --region frame --width 4096 --supersample 4 --out o",
            "--width x --supersample: expected at most 8192 rays across", kBadCommandLine},
           {"eval r --truth t --units metres --out o", "--units", kBadCommandLine},
           {"export r --out o", "give one of --vdb, --nerf, --mantaflow", kBadCommandLine},
           {"export r --out o --vdb --nerf", "--vdb excludes --nerf", kBadCommandLine},
           {"export r --out o --nerf --camera-error nan", "--camera-error: expected a number above 0", kBadCommandLine},
           {"export r --out o --mantaflow --camera-error 1", "--camera-error requires --nerf", kBadCommandLine},
           {"frobnicate", "unknown command 'frobnicate'", kBadCommandLine},
           {"train grho-coarse --data d --out o --steps 0", "--steps: expected a whole number", kBadCommandLine},
           {"train gu --data d --out o --config c.json --preset tiny", "--preset excludes --config", kBadCommandLine},
           {"train gu --data d --out o --resume --overwrite", "--resume excludes --overwrite", kBadCommandLine},
           {"reconstruct in.mp4 --out o --ddim-steps 0", "--ddim-steps: expected a whole number", kBadCommandLine},
           {"reconstruct in.mp4 --out o --polish-lr 0", "--polish-lr: expected a number above 0", kBadCommandLine},
           {"reconstruct in.mp4 --out o --polish-prior-weight -1", "--polish-prior-weight: expected a number from 0",
            kBadCommandLine},
           {"reconstruct in.mp4 --out o --side-views s --side-view mirror",
            "--side-views gives the side views; it cannot be combined with --side-view mirror", kFailed},
       })
    expectOneLineError(c);
}

TEST_F(BadInputTest, HelpOfARealCommandStillWorks) {
  const CommandResult result = runSmokesvd("render --help");
  EXPECT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("--overlay-frame"), std::string::npos);
  EXPECT_NE(result.out.find("1..8192"), std::string::npos) << "bounds are shown in the help";
}

TEST_F(BadInputTest, SizesAreBoundedBeforeAnythingIsAllocated) {
  const std::string info = calibration();
  for (const BadInput& c : std::vector<BadInput>{
           // Each of these once ran for minutes or ran out of memory.
           {"render --cameras " + info + " --overlay-frame 1 --grid 100000,1,1 --out " + path("o.png"),
            "--grid: expected D,H,W, three whole numbers from 1 to 1024, got '100000,1,1'"},
           {"render --cameras " + info + " --overlay-frame 1 --grid 2048,2048,2048 --out " + path("o.png"), "--grid"},
           {"render --cameras " + info + " --overlay-frame 1 --grid 1e30,1,1 --out " + path("o.png"), "--grid"},
           {"render --cameras " + info + " --overlay-frame 1 --grid 1024,1024,1024 --out " + path("o.png"),
            "more than the 268435456 smokesvd accepts"},
           {"render " + volume("v.npy") + " --turntable 3600 --width 8192 --height 8192 --out " + path("o"),
            "more than the 268435456 one render may hold"},
       })
    expectOneLineError(c);
  // A volume file of a huge grid: refused from its header.
  io::writeNpy(path("long.npy"), io::NpyArray::fromFloats({1, 1, 2000}, std::vector<float>(2000, 0.0f)));
  expectOneLineError({"render " + path("long.npy") + " --out " + path("o"), "long.npy: grid 2000 x 1 x 1"});
}

TEST_F(BadInputTest, FoldersWhereFilesAreExpected) {
  for (const char* name : {"folder.npy", "folder.npz", "folder.json"}) fs::create_directories(path(name));
  for (const BadInput& c : std::vector<BadInput>{
           {"render " + path("folder.npy") + " --out " + path("o"), "folder.npy: is a folder, expected a file"},
           {"render " + path("folder.npz") + " --out " + path("o"), "folder.npz: is a folder, expected a file"},
           {"render " + volume("v.npy") + " --cameras " + path("folder.json") + " --out " + path("o"),
            "folder.json: is a folder, expected a file"},
           {"op relu --in x=" + path("folder.npy") + " --out y=" + path("y.npy"), "folder.npy: is a folder, expected a file"},
           {"simulate --scene " + path("folder.json") + " --out " + path("s"), "folder.json: is a folder, expected a file"},
           {"render " + path("missing.npy") + " --out " + path("o"), "missing.npy: no such file"},
       })
    expectOneLineError(c);
}

TEST_F(BadInputTest, NonFiniteInputNamesTheFileAndTheFirstBadElement) {
  for (const BadInput& c : std::vector<BadInput>{
           {"render " + volume("nan.npy", std::nanf("")) + " --out " + path("o"),
            "nan.npy: element [1, 1, 1] of [4, 5, 6] is nan (densities must be finite)"},
           {"render " + volume("inf.npy", std::numeric_limits<float>::infinity()) + " --out " + path("o"),
            "inf.npy: element [1, 1, 1] of [4, 5, 6] is inf"},
           {"op relu --in x=" + volume("x.npy", -std::numeric_limits<float>::infinity()) + " --out y=" + path("y.npy"),
            "x.npy: element [1, 1, 1] of [4, 5, 6] is -inf (op inputs must be finite)"},
       })
    expectOneLineError(c);
}

TEST_F(BadInputTest, ScenesBeyondTheBoundsOfFloat32AreRefused) {
  std::vector<float> force(12 * 8 * 8 * 3, 0.0f);
  force[5] = std::nanf("");
  io::writeNpy(path("force.npy"), io::NpyArray::fromFloats({8, 12, 8, 3}, force));
  std::vector<float> huge(12 * 8 * 8 * 3, 3e38f);
  io::writeNpy(path("huge.npy"), io::NpyArray::fromFloats({8, 12, 8, 3}, huge));
  for (const BadInput& c : std::vector<BadInput>{
           {"simulate --scene " + scene("a.json", R"(, "buoyancy": {"density": 1e30})") + " --out " + path("s"),
            "field 'buoyancy.density': expected a number in [-10000.0, 10000.0], got 1e+30"},
           {"simulate --scene " + scene("b.json", R"(, "gravity": [0, 1e38, 0])") + " --out " + path("s"),
            "field 'gravity': expected three numbers [x, y, z] from -10000.0 to 10000.0"},
           {"simulate --scene " + scene("c.json", R"(, "sources": [{"shape": "sphere", "centre": [4, 2, 4], "radius": 1e30}])") +
                " --out " + path("s"),
            "field 'sources[0].radius': expected a number above 0 and at most 100000"},
           {"simulate --scene " + scene("d.json", R"(, "force_fields": [{"file": "force.npy"}])") + " --out " + path("s"),
            "force.npy: element [0, 0, 1, 2] of [8, 12, 8, 3] is nan (a force field times its scale must be finite)"},
           {"simulate --scene " + scene("e.json", R"(, "force_fields": [{"file": "huge.npy", "scale": 10}])") + " --out " +
                path("s"),
            "huge.npy: element [0, 0, 0, 0] of [8, 12, 8, 3] is inf"},
           {"simulate --scene " + scene("f.json", R"(, "resolution": [1024, 1024, 1024])") + " --out " + path("s"),
            "more than the 268435456 smokesvd accepts"},
       })
    expectOneLineError(c);
}

TEST_F(BadInputTest, FramesAreCappedAlikeInFlagsAndSceneFiles) {
  // The largest --frames is a scene file's largest "frames": what simulate writes, --scene reads.
  expectOneLineError({"simulate --scene " + scene("g.json", "") + " --frames 1000001 --out " + path("s"),
                      "--frames: expected a whole number from 1 to 1000000", kBadCommandLine});
  std::ofstream(path("h.json")) << R"({"resolution": [8, 12, 8], "frames": 1000001})";
  expectOneLineError({"simulate --scene " + path("h.json") + " --out " + path("s"),
                      "field 'frames': expected an integer in [1, 1000000]"});
}

TEST_F(BadInputTest, VideoEncoderProblemsSayWhy) {
  const std::string v = volume("v.npy");
  std::ofstream(path("not-executable")) << "#!/bin/sh\n";
  fs::create_directories(path("a-folder"));
  for (const std::string& ffmpeg : {path("not-executable"), path("a-folder")})
    expectOneLineError({"render " + v + " --turntable 2 --mp4 --preset tiny --out " + path("o"),
                        "SMOKESVD_FFMPEG=" + ffmpeg + " is not an executable file", kFailed, "SMOKESVD_FFMPEG=" + ffmpeg});
  // An ffmpeg that fails: its own last words are the cause.
  std::ofstream(path("failing")) << "#!/bin/sh\necho 'Unknown encoder libx264' >&2\nexit 1\n";
  fs::permissions(path("failing"), fs::perms::owner_all);
  expectOneLineError({"render " + v + " --turntable 2 --mp4 --preset tiny --out " + path("o"),
                      "encoding failed (ffmpeg: Unknown encoder libx264)", kFailed, "SMOKESVD_FFMPEG=" + path("failing")});
}

TEST_F(BadInputTest, TwoVolumesOfOneNameWouldOverwriteEachOther) {
  fs::create_directories(path("a"));
  fs::create_directories(path("b"));
  io::writeNpy(path("a/density_0040.npy"), io::NpyArray::fromFloats({4, 5, 6}, std::vector<float>(120, 0.5f)));
  io::writeNpy(path("b/density_0040.npy"), io::NpyArray::fromFloats({4, 5, 6}, std::vector<float>(120, 0.5f)));
  expectOneLineError({"render " + path("a/density_0040.npy") + " " + path("b/density_0040.npy") + " --out " + path("r"),
                      "would both write density_0040_*.png"});
  EXPECT_FALSE(fs::exists(path("r"))) << "nothing is written before the refusal";
}

}  // namespace
}  // namespace smokesvd::testing

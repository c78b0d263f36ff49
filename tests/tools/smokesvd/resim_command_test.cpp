// `smokesvd resim` as a user runs it, on a reconstruction-shaped folder made from a simulation
// (tests/harness/simulated_reconstruction.h): the outputs, --help, and bad inputs as one-line errors that
// leave everything as it was.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "pipeline/media/video.h"
#include "tests/harness/command.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/simulated_reconstruction.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

SimulatedReconstructionScratch& scratch() {
  static SimulatedReconstructionScratch folder("resim-cli", 4);
  return folder;
}
const io::TemporaryFolder& root() { return scratch().root(); }
const fs::path& reconstruction() { return scratch().reconstruction(); }

class ResimCli : public GpuTest {};

TEST_F(ResimCli, ContinuesPastTheVideoWithAnObstacleAndWritesVideos) {
  const fs::path out = root() / "ball";
  const CommandResult r = runSmokesvd("resim " + reconstruction().string() + " --out " + out.string() +
                                      " --obstacle sphere:8,8,8,2.5@2 --frames 6");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("6 frames in"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("departure from the reconstruction"), std::string::npos) << r.err;
  for (const char* f : {"scene.json", "flags.npz", "run.json", "fields/density_0005.npz", "fields/velocity_0005.npz",
                        "fields/inflow_0005.npz", "renders/view_08/0005.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  if (media::findFfmpeg()) {
    EXPECT_TRUE(fs::exists(out / "front.mp4"));
    EXPECT_TRUE(fs::exists(out / "side.mp4"));
  }
  // Again into the same folder: refused, then replaced with --overwrite.
  const CommandResult again = runSmokesvd("resim " + reconstruction().string() + " --out " + out.string() + " --no-videos");
  EXPECT_NE(again.exitCode, 0);
  EXPECT_NE(again.err.find("holds a re-simulation; --overwrite replaces it"), std::string::npos) << again.err;
  EXPECT_TRUE(fs::exists(out / "fields" / "density_0005.npz"));
  const CommandResult replaced =
      runSmokesvd("resim " + reconstruction().string() + " --out " + out.string() + " --no-videos --overwrite");
  ASSERT_EQ(replaced.exitCode, 0) << replaced.err;
  EXPECT_FALSE(fs::exists(out / "fields" / "density_0005.npz")) << "the new run has the reconstruction's 4 frames";
  EXPECT_FALSE(fs::exists(out / "front.mp4"));
}

TEST_F(ResimCli, HelpNamesEveryEdit) {
  const CommandResult r = runSmokesvd("resim --help");
  EXPECT_EQ(r.exitCode, 0);
  for (const char* option : {"--obstacle", "--force", "--upres", "--vorticity", "--inflow-scale", "--frames", "sphere:X,Y,Z,R"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
}

TEST_F(ResimCli, BadInputsAreOneLineErrorsAndNothingIsLost) {
  const fs::path scratch = root() / "bad";
  fs::create_directories(scratch / "stuff");
  std::ofstream(scratch / "stuff" / "notes.txt") << "mine";
  const std::string recon = reconstruction().string();
  const struct {
    std::string arguments, message;
  } cases[] = {
      {"resim " + (scratch / "stuff").string() + " --out " + (scratch / "o1").string(), "not a run folder"},
      {"resim " + recon + " --out " + (scratch / "o2").string() + " --obstacle sphere:8,40,8,2",
       "the centre lies outside the reconstruction's box [0, 16] x [0, 28] x [0, 16]"},
      {"resim " + recon + " --out " + (scratch / "o3").string() + " --obstacle box:1,2,3", "expected sphere:X,Y,Z,R"},
      {"resim " + recon + " --out " + (scratch / "o4").string() + " --force uniform:1,2", "expected three numbers"},
      {"resim " + recon + " --out " + (scratch / "stuff").string(), "is not empty and holds no re-simulation"},
      {"resim " + recon + " --out " + (scratch / "stuff" / "notes.txt" / "out").string(), "cannot create the output folder"},
      {"resim " + recon + " --out /proc/smokesvd-resim", "cannot create the output folder"},
  };
  for (const auto& c : cases) {
    const CommandResult r = runSmokesvd(c.arguments);
    EXPECT_NE(r.exitCode, 0) << c.arguments;
    EXPECT_EQ(countLines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("smokesvd: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
  }
  for (const char* created : {"o1", "o2", "o3", "o4"}) EXPECT_FALSE(fs::exists(scratch / created)) << created;
  EXPECT_EQ(std::distance(fs::directory_iterator(scratch / "stuff"), fs::directory_iterator()), 1);
  EXPECT_TRUE(fs::exists(reconstruction() / "run.json"));
}

}  // namespace
}  // namespace smokesvd::testing

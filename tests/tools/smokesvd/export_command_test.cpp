// `smokesvd export` as a user runs it on a reconstruction-shaped folder (tests/harness/simulated_reconstruction.h):
// each format, --help, and bad inputs as one-line errors that leave everything as it was.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "nets/io/temporary_folder.h"
#include "pipeline/export/export_run.h"
#include "tests/harness/command.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/simulated_reconstruction.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

SimulatedReconstructionScratch& scratch() {
  static SimulatedReconstructionScratch folder("export-cli", 2);
  return folder;
}
const io::TemporaryFolder& root() { return scratch().root(); }
const fs::path& reconstruction() { return scratch().reconstruction(); }

class ExportCli : public GpuTest {};

TEST_F(ExportCli, WritesEachFormat) {
  const std::string source = reconstruction().string();
  const CommandResult manta = runSmokesvd("export " + source + " --out " + (root() / "manta").string() + " --mantaflow");
  ASSERT_EQ(manta.exitCode, 0) << manta.err;
  EXPECT_NE(manta.err.find("2 frames"), std::string::npos) << manta.err;
  EXPECT_TRUE(fs::exists(root() / "manta" / "velocity_0001.npz"));
  const CommandResult nerf = runSmokesvd("export " + source + " --out " + (root() / "nerf").string() + " --nerf --camera-error 0.5");
  ASSERT_EQ(nerf.exitCode, 0) << nerf.err;
  EXPECT_TRUE(fs::exists(root() / "nerf" / "frame_0001" / "transforms.json"));
  const CommandResult vdb = runSmokesvd("export " + source + " --out " + (root() / "vdb").string() + " --vdb --z-up");
  if (exporters::openVdbAvailable()) {
    ASSERT_EQ(vdb.exitCode, 0) << vdb.err;
    EXPECT_TRUE(fs::exists(root() / "vdb" / "frame_0001.vdb"));
  } else {
    EXPECT_NE(vdb.exitCode, 0);
    EXPECT_EQ(countLines(vdb.err), 1) << vdb.err;
    EXPECT_NE(vdb.err.find("built without OpenVDB"), std::string::npos) << vdb.err;
    EXPECT_FALSE(fs::exists(root() / "vdb"));
  }
}

TEST_F(ExportCli, HelpNamesEveryFormat) {
  const CommandResult r = runSmokesvd("export --help");
  EXPECT_EQ(r.exitCode, 0);
  for (const char* option : {"--vdb", "--nerf", "--mantaflow", "--calibration", "--z-up", "--camera-error", "--overwrite"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
}

TEST_F(ExportCli, BadInputsAreOneLineErrorsAndNothingIsLost) {
  const fs::path scratch = root() / "bad";
  fs::create_directories(scratch / "stuff");
  std::ofstream(scratch / "stuff" / "notes.txt") << "mine";
  const std::string source = reconstruction().string();
  const struct {
    std::string arguments, message;
  } cases[] = {
      {"export " + source + " --out " + (scratch / "o1").string(), "give one of --vdb, --nerf, --mantaflow"},
      {"export " + source + " --out " + (scratch / "o2").string() + " --nerf --mantaflow", "--nerf excludes --mantaflow"},
      {"export " + (scratch / "stuff").string() + " --out " + (scratch / "o3").string() + " --nerf", "not a run folder"},
      {"export " + source + " --out " + (scratch / "stuff").string() + " --mantaflow", "is not empty and holds no export"},
      {"export " + source + " --out /proc/smokesvd-export --mantaflow", "cannot create the output folder"},
      {"export " + source + " --out " + (scratch / "o4").string() + " --nerf --calibration " + (scratch / "none.json").string(),
       "give its place with --calibration"},
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
}

}  // namespace
}  // namespace smokesvd::testing

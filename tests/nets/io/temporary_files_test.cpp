// A process ended by a signal removes the temporaries it was writing (nets/io/temporary_files.h).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>

#include "nets/io/temporary_files.h"
#include "nets/io/temporary_folder.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

TEST(TemporaryFilesTest, ASignalRemovesTheTemporariesInFlightAndEndsTheProcessAsTheSignalWould) {
  const io::TemporaryFolder folder("temporaries");
  const fs::path inFlight = folder / "density_0003.npz.tmp", finished = folder / "density_0002.npz.tmp";
  const fs::path kept = folder / "density_0002.npz";
  for (const fs::path& file : {inFlight, finished, kept}) std::ofstream(file) << "data";
  for (int signal : {SIGINT, SIGTERM, SIGHUP}) {
    std::ofstream(inFlight) << "data";
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      io::removeTemporariesOnSignals();
      { const io::InFlightTemporary done(finished); }  // written and renamed: no longer registered
      const io::InFlightTemporary writing(inFlight);
      std::raise(signal);
      ::_exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << "signal " << signal << ", status " << status;
    EXPECT_FALSE(fs::exists(inFlight)) << "signal " << signal;
    EXPECT_TRUE(fs::exists(finished)) << "only temporaries in flight are removed";
    EXPECT_TRUE(fs::exists(kept));
  }
}

// A job started in the background (SIGINT and SIGHUP ignored, as a shell and nohup start it) keeps ignoring them.
TEST(TemporaryFilesTest, ASignalTheProcessWasStartedIgnoringStaysIgnored) {
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGHUP, SIG_IGN);
    io::removeTemporariesOnSignals();
    std::raise(SIGHUP);
    ::_exit(std::signal(SIGHUP, SIG_DFL) == SIG_IGN ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
}

}  // namespace
}  // namespace smokesvd::testing

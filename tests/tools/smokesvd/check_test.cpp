#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "tests/harness/op_runner.h"

namespace smokesvd::testing {
namespace {

// `--check` (or SMOKESVD_CHECK=1) stops a command at the first kernel that writes a NaN or Inf.
TEST(CheckFlag, NamesTheKernelThatWroteTheFirstInfinity) {
  const std::map<std::string, io::NpyArray> x{{"x", io::NpyArray::fromFloats({2, 3}, {1, 2, 3, 4, 5, 6})}};
  // y = 1e38 x overflows to +Inf from x = 4 on, element 3.
  const auto run = [&](const std::string& flags) { return runOpCommand("scale", x, {"y"}, {"alpha=1e38"}, flags); };
  ::setenv("SMOKESVD_CHECK", "0", 1);
  EXPECT_EQ(run("").exitCode, 0);  // off unless asked for
  const OpRun flagged = run("--check");
  ::setenv("SMOKESVD_CHECK", "1", 1);
  const OpRun environment = run("");
  ::unsetenv("SMOKESVD_CHECK");
  for (const OpRun* result : {&flagged, &environment}) {
    EXPECT_NE(result->exitCode, 0);
    EXPECT_EQ(std::count(result->err.begin(), result->err.end(), '\n'), 1) << result->err;
    EXPECT_NE(result->err.find("smokesvd: error: finite check (SMOKESVD_CHECK): +Inf written by dispatch 1, "
                               "shader 'tensor/axpby', binding 2 'Output', at element 3 of 6, index [1, 0] of [2, 3]"),
              std::string::npos)
        << result->err;
  }
}

}  // namespace
}  // namespace smokesvd::testing

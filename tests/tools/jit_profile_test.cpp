#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "nets/io/temporary_folder.h"
#include "tests/harness/command.h"

namespace smokesvd::testing {
namespace {

// tools/jit_profile.py's report on a saved profile (--from): a made-up disassembly of two compiled
// functions, with padding between them, and five samples: three in the first function, one in the
// second, one outside both (the padding between them is not counted). Shares = samples in a function /
// all samples; the mix counts each function's instructions by kind. Skipped where no Python 3 is installed.

const std::string kTool = "python3 " SMOKESVD_SOURCE_DIR "/tools/jit_profile.py";

bool havePython() { return std::system("python3 -c '' >/dev/null 2>&1") == 0; }

TEST(JitProfileTest, ReportsEachCompiledFunctionsShareAndInstructionMix) {
  if (!havePython()) GTEST_SKIP() << "no python3 on this machine";
  const io::TemporaryFolder folder("jit-profile");
  {
    std::ofstream disassembly(folder / "jit.asm");
    disassembly << "   0x1000:\tpush   %rbp\n"
                   "   0x1001:\tcall   *%r12\n"
                   "   0x1004:\tvmulps %ymm1,%ymm2,%ymm3\n"
                   "   0x1008:\tvaddps %ymm3,%ymm4,%ymm4\n"
                   "   0x100c:\tvblendvps %ymm13,%ymm4,%ymm12,%ymm12\n"
                   "   0x1012:\tret\n"
                   "   0x1013:\tadd    %al,(%rax)\n"
                   "   0x1015:\tadd    %al,(%rax)\n"
                   "   0x1020:\tvpextrd $0x1,%xmm0,%ecx\n"
                   "   0x1026:\tvmovdqa (%rax,%rcx,1),%xmm1\n"
                   "   0x102b:\tret\n";
    std::ofstream samples(folder / "samples.txt");
    samples << "1004\n1004\n1004\n1020\nffffffff81000000\n";
  }
  const CommandResult result = runCommand(kTool + " --from " + folder.path().string() + " --top 1");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_EQ(result.out,
            "5 samples; per compiled function (share of all samples, instructions, mix):\n"
            "   60.0 %  0x1000      6 instructions: calls 1, multiplies 1, adds 1, blends 1\n"
            "   20.0 %  0x1020      3 instructions: vector moves 1, lane extracts 1\n"
            "   20.0 %  outside compiled shaders (driver, kernel, program)\n"
            "small leaf functions (under 100 instructions, no calls: the fetch helpers): 20.0 %\n"
            "the 1 hottest instructions:\n"
            "  60.00 %  0x1004  vmulps %ymm1,%ymm2,%ymm3\n");
}

TEST(JitProfileTest, AFolderWithoutAProfileIsAnErrorNamingWhatIsMissing) {
  if (!havePython()) GTEST_SKIP() << "no python3 on this machine";
  const io::TemporaryFolder folder("jit-profile");
  const CommandResult result = runCommand(kTool + " --from " + folder.path().string());
  EXPECT_NE(result.exitCode, 0);
  EXPECT_NE(result.err.find("no jit.asm (a folder written by --save holds jit.asm and samples.txt)"), std::string::npos)
      << result.err;
}

}  // namespace
}  // namespace smokesvd::testing

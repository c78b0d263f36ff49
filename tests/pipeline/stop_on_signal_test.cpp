// StopOnSignal: a first SIGINT or SIGTERM while it lives asks to stop instead of ending the process, and
// the handlers before it come back when it goes.
#include <gtest/gtest.h>

#include <csignal>

#include "pipeline/stop_on_signal.h"

namespace smokesvd::testing {
namespace {

int signalsSeen = 0;
void countSignal(int) { ++signalsSeen; }

TEST(StopOnSignal, AFirstSignalAsksToStopAndTheHandlersBeforeComeBack) {
  for (const int signal : {SIGINT, SIGTERM}) {
    signalsSeen = 0;
    auto* const before = std::signal(signal, countSignal);
    {
      const StopOnSignal stop;
      EXPECT_FALSE(stop.requested().load());
      std::raise(signal);  // handled: the test process goes on
      EXPECT_TRUE(stop.requested().load());
      EXPECT_EQ(signalsSeen, 0);
    }
    {
      const StopOnSignal again;  // a new job starts unasked
      EXPECT_FALSE(again.requested().load());
    }
    std::raise(signal);  // the handler from before StopOnSignal again
    EXPECT_EQ(signalsSeen, 1);
    std::signal(signal, before);
  }
}

TEST(StopOnSignal, ASignalTheProcessIgnoresStaysIgnored) {
  auto* const before = std::signal(SIGINT, SIG_IGN);
  {
    const StopOnSignal stop;
    std::raise(SIGINT);
    EXPECT_FALSE(stop.requested().load());
  }
  EXPECT_EQ(std::signal(SIGINT, before), SIG_IGN);
}

}  // namespace
}  // namespace smokesvd::testing

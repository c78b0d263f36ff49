// NameRegistry (runtime/name_registry.h): the one registry type behind ops, benchmarks and commands.
#include <gtest/gtest.h>

#include <string>

#include "nets/op_registry.h"
#include "runtime/error.h"
#include "runtime/name_registry.h"
#include "tools/bench/bench.h"

namespace smokesvd::testing {
namespace {

struct Named {
  std::string name;
  int value = 0;
};

TEST(NameRegistry, KeepsEntriesSortedAndFindsThem) {
  NameRegistry<Named> registry("thing");
  EXPECT_TRUE(registry.add({"pear", 1}));
  EXPECT_TRUE(registry.add({"apple", 2}));
  EXPECT_TRUE(registry.add({"fig", 3}));
  ASSERT_EQ(registry.all().size(), 3u);
  EXPECT_EQ(registry.all()[0].name, "apple");
  EXPECT_EQ(registry.all()[1].name, "fig");
  EXPECT_EQ(registry.all()[2].name, "pear");
  ASSERT_NE(registry.find("fig"), nullptr);
  EXPECT_EQ(registry.find("fig")->value, 3);
  EXPECT_EQ(registry.find("plum"), nullptr);
  EXPECT_EQ(registry.find("app"), nullptr);
}

TEST(NameRegistry, RejectsADuplicateName) {
  NameRegistry<Named> registry("benchmark");
  registry.add({"copy/texel", 1});
  try {
    registry.add({"copy/texel", 2});
    ADD_FAILURE() << "a duplicate name was accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "benchmark 'copy/texel' is registered twice");
  }
  ASSERT_EQ(registry.all().size(), 1u);
  EXPECT_EQ(registry.find("copy/texel")->value, 1);
}

// The program's own registries are NameRegistries: registering a name again is refused.
TEST(NameRegistry, OpsAndBenchmarksRefuseANameTwice) {
  ASSERT_FALSE(registeredOps().empty());
  OpSpec again = registeredOps().front();
  EXPECT_THROW(registerOp(again), Error);
  ASSERT_FALSE(bench::benchmarks().empty());
  EXPECT_THROW(bench::registerBenchmark(bench::benchmarks().front()), Error);
}

}  // namespace
}  // namespace smokesvd::testing

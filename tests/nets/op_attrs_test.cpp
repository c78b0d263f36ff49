// The one number-list parser (nets/op_registry.h) behind op attributes and command-line flags.
#include <gtest/gtest.h>

#include <string>

#include "nets/op_registry.h"
#include "runtime/error.h"

namespace smokesvd::testing {
namespace {

std::string errorOf(const std::string& text, const std::string& what) {
  try {
    parseNumberList(text, what);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(NumberList, ParsesCommaSeparatedFiniteNumbers) {
  EXPECT_EQ(parseNumberList("0,22.5,-90,1e3", "--angles"), (std::vector<double>{0, 22.5, -90, 1000}));
  EXPECT_EQ(parseNumberList("7", "--angles"), (std::vector<double>{7}));
}

TEST(NumberList, ErrorsNameTheFlagAndTheText) {
  for (const std::string bad : {"", "1,,2", ",1", "1,2,", "1;2", "x", "1,nan", "inf", "1 2"})
    EXPECT_EQ(errorOf(bad, "--angles"), "--angles: '" + bad + "' is not a comma-separated list of numbers") << bad;
}

TEST(NumberList, OpAttrsNumbersAndIntegersUseIt) {
  const OpAttrs attrs("demo", {{"angles", "0,90.5"}, {"axes", "1,-2,3"}, {"half", "1,2.5"}, {"word", "a,b"}});
  EXPECT_EQ(attrs.numbers("angles"), (std::vector<double>{0, 90.5}));
  EXPECT_EQ(attrs.integers("axes"), (std::vector<int64_t>{1, -2, 3}));
  try {
    attrs.integers("half");
    ADD_FAILURE() << "a fraction was accepted as an integer";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "op demo: attribute half='1,2.5' is not a comma-separated integer list");
  }
  try {
    attrs.numbers("word");
    ADD_FAILURE() << "words were accepted as numbers";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "op demo: attribute word: 'a,b' is not a comma-separated list of numbers");
  }
}

}  // namespace
}  // namespace smokesvd::testing

// Reading a JSON file: its value, or an error naming the file, what is wrong and the remedy.
#include <gtest/gtest.h>

#include <fstream>

#include "nets/io/json_file.h"
#include "nets/io/temporary_folder.h"
#include "runtime/error.h"

namespace smokesvd::testing {
namespace {

std::string errorOf(const std::filesystem::path& path, const std::string& remedy = "") {
  try {
    io::readJsonFile(path, remedy);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(JsonFileTest, ReadsTheValue) {
  const io::TemporaryFolder folder("json-file");
  std::ofstream(folder / "run.json") << R"({"frames": 12, "complete": true})";
  const nlohmann::json run = io::readJsonFile(folder / "run.json");
  EXPECT_EQ(run["frames"], 12);
  EXPECT_EQ(run["complete"], true);
}

TEST(JsonFileTest, NamesTheFileTheReasonAndTheRemedy) {
  const io::TemporaryFolder folder("json-file");
  const std::filesystem::path broken = folder / "config.json";
  std::ofstream(broken) << R"({"frames": 12,)";
  const std::string withRemedy = errorOf(broken, "delete it");
  EXPECT_NE(withRemedy.find(broken.string() + ": not valid JSON ("), std::string::npos) << withRemedy;
  EXPECT_NE(withRemedy.find("); delete it"), std::string::npos) << withRemedy;
  const std::string plain = errorOf(broken);
  EXPECT_EQ(plain.back(), ')') << plain;
  const std::string missing = errorOf(folder / "absent.json");
  EXPECT_NE(missing.find("absent.json"), std::string::npos) << missing;
  EXPECT_NE(missing.find("no such file"), std::string::npos) << missing;
}

}  // namespace
}  // namespace smokesvd::testing

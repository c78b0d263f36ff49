#include "nets/io/json_file.h"

#include "nets/io/file_io.h"
#include "runtime/error.h"

namespace smokesvd::io {

nlohmann::json readJsonFile(const std::filesystem::path& path, const std::string& remedy) {
  const std::string text = readTextFile(path);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    throw Error(path.string() + ": not valid JSON (" + error.what() + ")" + (remedy.empty() ? "" : "; " + remedy));
  }
}

void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& json) {
  writeTextFileAtomically(path, json.dump(2) + "\n");
}

}  // namespace smokesvd::io

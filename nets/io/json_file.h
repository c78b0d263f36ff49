// Reading a JSON file with errors that name it, and writing one atomically.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace smokesvd::io {

// The parsed file. Throws Error naming the path when it cannot be read (readTextFile's errors) or is not
// valid JSON ("<path>: not valid JSON (<parser's reason>)", then "; <remedy>" when one is given).
nlohmann::json readJsonFile(const std::filesystem::path& path, const std::string& remedy = "");

// Writes `json` indented by two spaces, with a final newline, atomically (file_io.h).
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& json);

}  // namespace smokesvd::io

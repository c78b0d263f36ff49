// Whole-file reads and atomic writes shared by the file formats: a write goes to "<path>.tmp" and is
// renamed into place, so an interrupted write never leaves a half-written file under the real name.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "nets/io/temporary_files.h"

namespace smokesvd::io {

// The whole file. Throws Error naming the path: "no such file", "is a folder, expected a file", or why it
// cannot be read.
std::vector<std::byte> readFileBytes(const std::filesystem::path& path);
std::string readTextFile(const std::filesystem::path& path);
// Throws the same errors as the readers unless `path` names an existing file (not a folder).
void requireReadableFile(const std::filesystem::path& path);

// Calls write(temporaryPath), then renames the temporary over `path`; removes it if anything throws, and
// a signal that ends the process meanwhile removes it too (temporary_files.h).
template <typename Write>
void writeAtomically(const std::filesystem::path& path, Write&& write) {
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  const InFlightTemporary inFlight(temporary);
  try {
    write(temporary);
    std::filesystem::rename(temporary, path);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

void writeFileAtomically(const std::filesystem::path& path, const std::vector<std::byte>& bytes);
void writeTextFileAtomically(const std::filesystem::path& path, const std::string& text);

}  // namespace smokesvd::io

// Whole-file reads and atomic writes shared by the file formats: a write goes to "<path>.tmp" and is
// renamed into place, so an interrupted write never leaves a half-written file under the real name.
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

namespace smokesvd::io {

std::vector<std::byte> readFileBytes(const std::filesystem::path& path);

// Calls write(temporaryPath), then renames the temporary over `path`; removes it if anything throws.
template <typename Write>
void writeAtomically(const std::filesystem::path& path, Write&& write) {
  std::filesystem::path temporary = path;
  temporary += ".tmp";
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

}  // namespace smokesvd::io

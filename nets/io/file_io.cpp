#include "nets/io/file_io.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include "runtime/error.h"

namespace smokesvd::io {

void requireReadableFile(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw Error(path.string() + ": no such file");
  if (std::filesystem::is_directory(status)) throw Error(path.string() + ": is a folder, expected a file");
}

std::string readTextFile(const std::filesystem::path& path) {
  requireReadableFile(path);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(path.string() + ": cannot open for reading: " + std::strerror(errno));
  std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) throw Error(path.string() + ": reading failed");
  return text;
}

std::vector<std::byte> readFileBytes(const std::filesystem::path& path) {
  const std::string text = readTextFile(path);
  const auto* first = reinterpret_cast<const std::byte*>(text.data());
  return std::vector<std::byte>(first, first + text.size());
}

void writeFileAtomically(const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
  writeAtomically(path, [&](const std::filesystem::path& temporary) {
    std::ofstream file(temporary, std::ios::binary);
    file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    file.close();
    if (!file) throw Error(path.string() + ": write failed");
  });
}

void writeTextFileAtomically(const std::filesystem::path& path, const std::string& text) {
  writeAtomically(path, [&](const std::filesystem::path& temporary) {
    std::ofstream file(temporary, std::ios::binary);
    file << text;
    file.close();
    if (!file) throw Error(path.string() + ": write failed");
  });
}

}  // namespace smokesvd::io

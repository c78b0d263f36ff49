#include "nets/io/file_io.h"

#include <cstring>
#include <fstream>
#include <iterator>

#include "runtime/error.h"

namespace smokesvd::io {

std::vector<std::byte> readFileBytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(path.string() + ": cannot open for reading");
  std::vector<char> raw((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::vector<std::byte> bytes(raw.size());
  std::memcpy(bytes.data(), raw.data(), raw.size());
  return bytes;
}

void writeFileAtomically(const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
  writeAtomically(path, [&](const std::filesystem::path& temporary) {
    std::ofstream file(temporary, std::ios::binary);
    file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    file.close();
    if (!file) throw Error(path.string() + ": write failed");
  });
}

}  // namespace smokesvd::io

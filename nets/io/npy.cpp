#include "nets/io/npy.h"

#include <zip.h>

#include <cstring>
#include <ctime>
#include <fstream>
#include <memory>
#include <regex>

#include "nets/io/file_io.h"
#include "runtime/error.h"

namespace smokesvd::io {
namespace {

constexpr char kMagic[] = "\x93NUMPY";

Error fail(const std::string& source, const std::string& what) { return Error(source + ": " + what); }

std::string quoted(const std::string& header, const std::string& key, const std::string& source) {
  const std::regex pattern("'" + key + "'\\s*:\\s*'([^']*)'");
  std::smatch match;
  if (!std::regex_search(header, match, pattern)) throw fail(source, "npy header has no '" + key + "' field");
  return match[1];
}

Shape parseShape(const std::string& header, const std::string& source) {
  const std::regex pattern("'shape'\\s*:\\s*\\(([^)]*)\\)");
  std::smatch match;
  if (!std::regex_search(header, match, pattern)) throw fail(source, "npy header has no 'shape' tuple");
  Shape shape;
  const std::string dims = match[1];
  const std::regex number("\\d+");
  for (auto it = std::sregex_iterator(dims.begin(), dims.end(), number); it != std::sregex_iterator(); ++it)
    shape.push_back(std::stoll(it->str()));
  return shape;
}

}  // namespace

std::vector<float> NpyArray::toFloat() const {
  if (dtype == DType::Float32) return floats;
  return std::vector<float>(ints.begin(), ints.end());
}

NpyArray NpyArray::fromFloats(Shape shape, std::vector<float> values) {
  NpyArray array;
  array.shape = std::move(shape);
  array.dtype = DType::Float32;
  array.floats = std::move(values);
  return array;
}

NpyArray NpyArray::fromInts(Shape shape, std::vector<int32_t> values) {
  NpyArray array;
  array.shape = std::move(shape);
  array.dtype = DType::Int32;
  array.ints = std::move(values);
  return array;
}

NpyArray parseNpy(std::span<const std::byte> bytes, const std::string& source) {
  if (bytes.size() < 10 || std::memcmp(bytes.data(), kMagic, 6) != 0) throw fail(source, "not a .npy file (bad magic)");
  const auto major = static_cast<uint8_t>(bytes[6]);
  std::size_t headerLength = 0, headerStart = 0;
  if (major == 1) {
    headerLength = static_cast<std::size_t>(bytes[8]) | static_cast<std::size_t>(bytes[9]) << 8;
    headerStart = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw fail(source, "truncated .npy header");
    for (int i = 0; i < 4; ++i) headerLength |= static_cast<std::size_t>(bytes[8 + i]) << (8 * i);
    headerStart = 12;
  } else {
    throw fail(source, "unsupported .npy format version " + std::to_string(major) + " (expected 1, 2 or 3)");
  }
  if (headerStart + headerLength > bytes.size()) throw fail(source, "truncated .npy header");
  const std::string header(reinterpret_cast<const char*>(bytes.data() + headerStart), headerLength);

  NpyArray array;
  const std::string descr = quoted(header, "descr", source);
  if (descr == "<f4") array.dtype = DType::Float32;
  else if (descr == "<i4") array.dtype = DType::Int32;
  else throw fail(source, "dtype '" + descr + "' is not supported (expected '<f4' float32 or '<i4' int32)");
  if (header.find("'fortran_order': False") == std::string::npos)
    throw fail(source, "fortran_order must be False (C order); save with np.ascontiguousarray");
  array.shape = parseShape(header, source);
  for (int64_t extent : array.shape)
    if (extent < 0) throw fail(source, "negative dimension in shape");

  const std::size_t dataStart = headerStart + headerLength;
  const std::size_t expected = static_cast<std::size_t>(array.numel()) * 4;
  const std::size_t available = bytes.size() - dataStart;
  if (available != expected) {
    throw fail(source, "shape " + toString(array.shape) + " needs " + std::to_string(expected) +
                           " data bytes but the file holds " + std::to_string(available));
  }
  if (array.dtype == DType::Float32) {
    array.floats.resize(static_cast<std::size_t>(array.numel()));
    std::memcpy(array.floats.data(), bytes.data() + dataStart, expected);
  } else {
    array.ints.resize(static_cast<std::size_t>(array.numel()));
    std::memcpy(array.ints.data(), bytes.data() + dataStart, expected);
  }
  return array;
}

std::vector<std::byte> serializeNpy(const NpyArray& array) {
  std::string shape = "(";
  for (std::size_t i = 0; i < array.shape.size(); ++i) shape += std::to_string(array.shape[i]) + ", ";
  if (array.shape.size() > 1) shape.erase(shape.size() - 2);
  else if (array.shape.size() == 1) shape.erase(shape.size() - 1);
  shape += ")";
  std::string header = std::string("{'descr': '") + (array.dtype == DType::Float32 ? "<f4" : "<i4") +
                       "', 'fortran_order': False, 'shape': " + shape + ", }";
  const std::size_t unpadded = 10 + header.size() + 1;  // magic+version+length, header, newline
  header.append((64 - unpadded % 64) % 64, ' ');
  header += '\n';
  const std::size_t count = static_cast<std::size_t>(array.numel());
  const std::size_t have = array.dtype == DType::Float32 ? array.floats.size() : array.ints.size();
  if (have != count)
    throw Error("npy: array of shape " + toString(array.shape) + " holds " + std::to_string(have) + " values");
  std::vector<std::byte> bytes(10 + header.size() + count * 4);
  std::memcpy(bytes.data(), kMagic, 6);
  bytes[6] = std::byte{1};
  bytes[7] = std::byte{0};
  bytes[8] = static_cast<std::byte>(header.size() & 0xff);
  bytes[9] = static_cast<std::byte>(header.size() >> 8);
  std::memcpy(bytes.data() + 10, header.data(), header.size());
  const void* data = array.dtype == DType::Float32 ? static_cast<const void*>(array.floats.data()) : array.ints.data();
  if (count) std::memcpy(bytes.data() + 10 + header.size(), data, count * 4);
  return bytes;
}

NpyArray readNpy(const std::filesystem::path& path) { return parseNpy(readFileBytes(path), path.string()); }

void writeNpy(const std::filesystem::path& path, const NpyArray& array) {
  writeFileAtomically(path, serializeNpy(array));
}

namespace {

struct ZipCloser {
  void operator()(zip_t* archive) const { zip_discard(archive); }
};
using ZipHandle = std::unique_ptr<zip_t, ZipCloser>;

ZipHandle openZip(const std::filesystem::path& path) {
  int error = 0;
  zip_t* archive = zip_open(path.c_str(), ZIP_RDONLY, &error);
  if (!archive) {
    zip_error_t details;
    zip_error_init_with_code(&details, error);
    const std::string message = zip_error_strerror(&details);
    zip_error_fini(&details);
    throw Error(path.string() + ": cannot open as .npz (zip): " + message);
  }
  return ZipHandle(archive);
}

std::vector<std::byte> readMember(zip_t* archive, zip_uint64_t index, const std::string& source) {
  zip_stat_t stat;
  if (zip_stat_index(archive, index, 0, &stat) != 0) throw fail(source, "cannot read zip entry");
  std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> file(zip_fopen_index(archive, index, 0), zip_fclose);
  if (!file) throw fail(source, std::string("cannot open zip entry: ") + zip_strerror(archive));
  std::vector<std::byte> bytes(stat.size);
  const zip_int64_t read = zip_fread(file.get(), bytes.data(), stat.size);
  if (read < 0 || static_cast<zip_uint64_t>(read) != stat.size) throw fail(source, "truncated or corrupt zip entry");
  return bytes;
}

std::string keyOf(const std::string& member) {
  return member.size() > 4 && member.ends_with(".npy") ? member.substr(0, member.size() - 4) : member;
}

}  // namespace

std::map<std::string, NpyArray> readNpz(const std::filesystem::path& path) {
  ZipHandle archive = openZip(path);
  std::map<std::string, NpyArray> arrays;
  const zip_int64_t count = zip_get_num_entries(archive.get(), 0);
  for (zip_int64_t i = 0; i < count; ++i) {
    const std::string member = zip_get_name(archive.get(), static_cast<zip_uint64_t>(i), 0);
    const std::string source = path.string() + ":" + member;
    arrays[keyOf(member)] = parseNpy(readMember(archive.get(), static_cast<zip_uint64_t>(i), source), source);
  }
  return arrays;
}

NpyArray readNpzMember(const std::filesystem::path& path, const std::string& key) {
  ZipHandle archive = openZip(path);
  const zip_int64_t index = zip_name_locate(archive.get(), (key + ".npy").c_str(), 0);
  if (index < 0) {
    std::string keys;
    const zip_int64_t count = zip_get_num_entries(archive.get(), 0);
    for (zip_int64_t i = 0; i < count; ++i)
      keys += (keys.empty() ? "" : ", ") + keyOf(zip_get_name(archive.get(), static_cast<zip_uint64_t>(i), 0));
    throw Error(path.string() + ": no array '" + key + "' (available: " + keys + ")");
  }
  const std::string source = path.string() + ":" + key + ".npy";
  return parseNpy(readMember(archive.get(), static_cast<zip_uint64_t>(index), source), source);
}

// 1980-01-01 00:00:00 UTC, the earliest time a zip entry can hold.
constexpr time_t kFixedModificationTime = 315532800;

void writeNpz(const std::filesystem::path& path, const std::map<std::string, NpyArray>& arrays, bool compress) {
  writeAtomically(path, [&](const std::filesystem::path& temporary) {
    int error = 0;
    zip_t* archive = zip_open(temporary.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
    if (!archive) throw Error(path.string() + ": cannot create .npz");
    ZipHandle guard(archive);
    std::vector<std::vector<std::byte>> payloads;
    payloads.reserve(arrays.size());
    for (const auto& [key, array] : arrays) {
      payloads.push_back(serializeNpy(array));
      zip_source_t* source = zip_source_buffer(archive, payloads.back().data(), payloads.back().size(), 0);
      const zip_int64_t index = source ? zip_file_add(archive, (key + ".npy").c_str(), source, ZIP_FL_OVERWRITE) : -1;
      if (index < 0) {
        if (source) zip_source_free(source);
        throw Error(path.string() + ": cannot add array '" + key + "': " + zip_strerror(archive));
      }
      zip_set_file_compression(archive, static_cast<zip_uint64_t>(index), compress ? ZIP_CM_DEFLATE : ZIP_CM_STORE, 1);
      // A fixed time stamp: the same arrays give the same bytes, so reruns of a seeded scene compare equal.
      zip_file_set_mtime(archive, static_cast<zip_uint64_t>(index), kFixedModificationTime, 0);
    }
    if (zip_close(guard.get()) != 0) throw Error(path.string() + ": writing .npz failed: " + zip_strerror(guard.get()));
    guard.release();
  });
}

}  // namespace smokesvd::io

#include "nets/io/npy.h"

#include <zip.h>

#include <cstring>
#include <ctime>
#include <fstream>
#include <memory>
#include <algorithm>
#include <cctype>
#include <utility>

#include "nets/io/file_io.h"
#include "runtime/error.h"

namespace smokesvd::io {
namespace {

constexpr char kMagic[] = "\x93NUMPY";

Error fail(const std::string& source, const std::string& what) { return Error(source + ": " + what); }

// The header dictionary, e.g. {'descr': '<f4', 'fortran_order': False, 'shape': (16, 28, 16), }, parsed
// exactly: the three keys NumPy writes, each once, and nothing else.
struct NpyHeader {
  std::string descr;
  bool fortranOrder = false;
  Shape shape;
};

class HeaderParser {
 public:
  HeaderParser(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  NpyHeader parse() {
    NpyHeader header;
    bool haveDescr = false, haveOrder = false, haveShape = false;
    expect('{');
    while (!peek('}')) {
      const std::string key = quotedString();
      expect(':');
      bool* seen = key == "descr" ? &haveDescr : key == "fortran_order" ? &haveOrder : key == "shape" ? &haveShape : nullptr;
      if (!seen) throw fail(source_, "npy header has an unknown key '" + key + "' (expected descr, fortran_order, shape)");
      if (*seen) throw fail(source_, "npy header gives '" + key + "' twice");
      *seen = true;
      if (key == "descr") header.descr = quotedString();
      else if (key == "fortran_order") header.fortranOrder = boolean();
      else header.shape = shape();
      if (!peek('}')) expect(',');
    }
    expect('}');
    skipBlanks();
    if (position_ != text_.size()) throw fail(source_, "npy header has text after its dictionary");
    if (!haveDescr) throw fail(source_, "npy header has no 'descr' field");
    if (!haveOrder) throw fail(source_, "npy header has no 'fortran_order' field");
    if (!haveShape) throw fail(source_, "npy header has no 'shape' tuple");
    return header;
  }

 private:
  void skipBlanks() {
    while (position_ < text_.size() && (text_[position_] == ' ' || text_[position_] == '\n' || text_[position_] == '\t'))
      ++position_;
  }
  bool peek(char c) {
    skipBlanks();
    return position_ < text_.size() && text_[position_] == c;
  }
  void expect(char c) {
    if (!peek(c)) throw fail(source_, std::string("npy header: expected '") + c + "' at character " + std::to_string(position_));
    ++position_;
  }
  std::string quotedString() {
    skipBlanks();
    const char quote = position_ < text_.size() ? text_[position_] : '\0';
    if (quote != '\'' && quote != '"') throw fail(source_, "npy header: expected a quoted name at character " + std::to_string(position_));
    const std::size_t close = text_.find(quote, position_ + 1);
    if (close == std::string::npos) throw fail(source_, "npy header: unterminated string");
    std::string value = text_.substr(position_ + 1, close - position_ - 1);
    position_ = close + 1;
    return value;
  }
  bool boolean() {
    skipBlanks();
    for (const auto& [word, value] : {std::pair{"True", true}, std::pair{"False", false}})
      if (text_.compare(position_, std::strlen(word), word) == 0) {
        position_ += std::strlen(word);
        return value;
      }
    throw fail(source_, "npy header: 'fortran_order' must be True or False");
  }
  Shape shape() {
    Shape dims;
    expect('(');
    while (!peek(')')) {
      skipBlanks();
      if (position_ < text_.size() && text_[position_] == '-')
        throw fail(source_, "npy header: negative dimension in shape (" + shapeText() + ")");
      const std::size_t first = position_;
      int64_t extent = 0;
      while (position_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[position_]))) {
        if (__builtin_mul_overflow(extent, 10, &extent) || __builtin_add_overflow(extent, text_[position_] - '0', &extent))
          throw fail(source_, "npy header: a dimension of the shape (" + shapeText() + ") is too large");
        ++position_;
      }
      if (position_ == first) throw fail(source_, "npy header: the shape (" + shapeText() + ") is not a tuple of whole numbers");
      dims.push_back(extent);
      if (!peek(')')) expect(',');
    }
    expect(')');
    return dims;
  }
  // The shape tuple as written, for errors.
  std::string shapeText() const {
    const std::size_t open = text_.rfind('(', position_);
    const std::size_t close = text_.find(')', position_);
    return open == std::string::npos ? "?" : text_.substr(open + 1, (close == std::string::npos ? text_.size() : close) - open - 1);
  }

  const std::string& text_;
  const std::string& source_;
  std::size_t position_ = 0;
};

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

  const NpyHeader parsed = HeaderParser(header, source).parse();
  NpyArray array;
  if (parsed.descr == "<f4") array.dtype = DType::Float32;
  else if (parsed.descr == "<i4") array.dtype = DType::Int32;
  else throw fail(source, "dtype '" + parsed.descr + "' is not supported (expected '<f4' float32 or '<i4' int32)");
  if (parsed.fortranOrder) throw fail(source, "fortran_order must be False (C order); save with np.ascontiguousarray");
  array.shape = parsed.shape;

  const std::size_t dataStart = headerStart + headerLength;
  const std::size_t available = bytes.size() - dataStart;
  int64_t count = 1;
  for (int64_t extent : array.shape)
    if (__builtin_mul_overflow(count, extent, &count) || count > static_cast<int64_t>(available))
      count = -1;  // more elements than the file could hold
  const std::size_t expected = count < 0 ? 0 : static_cast<std::size_t>(count) * 4;
  if (count < 0 || available != expected) {
    if (count < 0)
      throw fail(source, "shape " + toString(array.shape) + " needs more data than the file's " +
                             std::to_string(available) + " bytes");
    throw fail(source, "shape " + toString(array.shape) + " needs " + std::to_string(expected) +
                           " data bytes but the file holds " + std::to_string(available));
  }
  // (memcpy only with bytes to copy: an empty vector's data() may be null, which memcpy must not get.)
  if (array.dtype == DType::Float32) {
    array.floats.resize(static_cast<std::size_t>(array.numel()));
    if (expected > 0) std::memcpy(array.floats.data(), bytes.data() + dataStart, expected);
  } else {
    array.ints.resize(static_cast<std::size_t>(array.numel()));
    if (expected > 0) std::memcpy(array.ints.data(), bytes.data() + dataStart, expected);
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
  requireReadableFile(path);
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

// The largest member read: a float field of kMaxGridCells vectors (3 GiB) and its header.
constexpr zip_uint64_t kMaxMemberBytes = (zip_uint64_t{4} << 30) + (1 << 20);

std::vector<std::byte> readMember(zip_t* archive, zip_uint64_t index, const std::string& source) {
  zip_stat_t stat;
  if (zip_stat_index(archive, index, 0, &stat) != 0 || !(stat.valid & ZIP_STAT_SIZE))
    throw fail(source, "cannot read zip entry");
  if (stat.size > kMaxMemberBytes)
    throw fail(source, "zip entry of " + std::to_string(stat.size) + " bytes, more than the " +
                           std::to_string(kMaxMemberBytes) + " an array may take");
  std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> file(zip_fopen_index(archive, index, 0), zip_fclose);
  if (!file) throw fail(source, std::string("cannot open zip entry: ") + zip_strerror(archive));
  // Read in chunks, so that a corrupt size claims no memory the data does not fill.
  std::vector<std::byte> bytes;
  std::vector<std::byte> chunk(1 << 20);
  while (bytes.size() < stat.size) {
    const zip_uint64_t want = std::min<zip_uint64_t>(chunk.size(), stat.size - bytes.size());
    const zip_int64_t read = zip_fread(file.get(), chunk.data(), want);
    if (read <= 0) break;
    bytes.insert(bytes.end(), chunk.begin(), chunk.begin() + read);
  }
  if (bytes.size() != stat.size) throw fail(source, "truncated or corrupt zip entry");
  return bytes;
}

// The name of member `index`; Error if the archive holds none.
std::string memberName(zip_t* archive, zip_uint64_t index, const std::filesystem::path& path) {
  const char* name = zip_get_name(archive, index, 0);
  if (name == nullptr) throw Error(path.string() + ": corrupt .npz (zip entry " + std::to_string(index) + " has no name)");
  return name;
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
    const std::string member = memberName(archive.get(), static_cast<zip_uint64_t>(i), path);
    const std::string source = path.string() + ":" + member;
    if (arrays.contains(keyOf(member))) throw Error(source + ": the archive holds '" + keyOf(member) + "' twice");
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
      keys += (keys.empty() ? "" : ", ") + keyOf(memberName(archive.get(), static_cast<zip_uint64_t>(i), path));
    throw Error(path.string() + ": no array '" + key + "' (available: " + keys + ")");
  }
  const std::string source = path.string() + ":" + key + ".npy";
  return parseNpy(readMember(archive.get(), static_cast<zip_uint64_t>(index), source), source);
}

// 1980-01-01 00:00:00 UTC, the earliest time a zip entry can hold.
constexpr time_t kFixedModificationTime = 315532800;

struct ZipSourceReleaser {
  void operator()(zip_source_t* source) const { zip_source_free(source); }
};
using ZipSourceHandle = std::unique_ptr<zip_source_t, ZipSourceReleaser>;

// The bytes a closed in-memory archive left in its buffer source.
std::vector<std::byte> bytesOfSource(zip_source_t* source, const std::filesystem::path& path) {
  zip_stat_t stat;
  zip_stat_init(&stat);
  if (zip_source_stat(source, &stat) != 0 || !(stat.valid & ZIP_STAT_SIZE) || zip_source_open(source) != 0)
    throw Error(path.string() + ": writing .npz failed: the archive cannot be read back from memory");
  std::vector<std::byte> bytes(static_cast<std::size_t>(stat.size));
  const zip_int64_t read = bytes.empty() ? 0 : zip_source_read(source, bytes.data(), bytes.size());
  zip_source_close(source);
  if (read != static_cast<zip_int64_t>(bytes.size()))
    throw Error(path.string() + ": writing .npz failed: the archive cannot be read back from memory");
  return bytes;
}

// The archive is built in memory and written with writeFileAtomically, so its only temporary file is the
// registered "<path>.tmp" (libzip writing to a file would leave a temporary of its own on a signal).
void writeNpz(const std::filesystem::path& path, const std::map<std::string, NpyArray>& arrays, bool compress) {
  zip_error_t error;
  zip_error_init(&error);
  ZipSourceHandle buffer(zip_source_buffer_create(nullptr, 0, 0, &error));
  zip_error_fini(&error);
  if (!buffer) throw Error(path.string() + ": cannot create .npz in memory");
  zip_source_keep(buffer.get());  // the archive releases its reference at close; ours keeps the bytes
  zip_error_init(&error);
  zip_t* archive = zip_open_from_source(buffer.get(), ZIP_TRUNCATE, &error);
  const std::string openError = zip_error_strerror(&error);
  zip_error_fini(&error);
  if (!archive) throw Error(path.string() + ": cannot create .npz: " + openError);
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
  if (arrays.empty()) {
    // libzip removes an archive of no entries; numpy writes its end-of-central-directory record alone.
    std::vector<std::byte> endRecord(22, std::byte{0});
    endRecord[0] = std::byte{'P'}, endRecord[1] = std::byte{'K'}, endRecord[2] = std::byte{5}, endRecord[3] = std::byte{6};
    writeFileAtomically(path, endRecord);
    return;
  }
  writeFileAtomically(path, bytesOfSource(buffer.get(), path));
}

}  // namespace smokesvd::io

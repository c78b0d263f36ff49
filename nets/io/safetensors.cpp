#include "nets/io/safetensors.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <unordered_map>

#include "nets/io/file_io.h"
#include "runtime/error.h"

namespace smokesvd::io {
namespace {

static_assert(std::endian::native == std::endian::little, "safetensors data is little-endian");

using Json = nlohmann::json;
constexpr uint64_t kMaxHeaderBytes = 100u << 20;  // the reference implementation's limit
constexpr const char* kMetadataKey = "__metadata__";

Error fail(const std::string& source, const std::string& what) { return Error(source + ": " + what); }

enum class StoredType { F32, F16, BF16, F64 };

struct TensorEntry {
  std::string name;
  StoredType type = StoredType::F32;
  Shape shape;
  uint64_t begin = 0;
  uint64_t end = 0;
};

uint64_t elementBytes(StoredType type) {
  switch (type) {
    case StoredType::F64: return 8;
    case StoredType::F32: return 4;
    case StoredType::F16:
    case StoredType::BF16: return 2;
  }
  return 4;
}

StoredType parseDType(const std::string& dtype, const std::string& where) {
  if (dtype == "F32") return StoredType::F32;
  if (dtype == "F16") return StoredType::F16;
  if (dtype == "BF16") return StoredType::BF16;
  if (dtype == "F64") return StoredType::F64;
  static const std::set<std::string> known = {"BOOL", "U8",  "I8",  "U16", "I16",     "U32",
                                              "I32",  "U64", "I64", "F8_E4M3", "F8_E5M2"};
  const std::string kind = known.count(dtype) ? "is not supported" : "is not a safetensors dtype";
  throw Error(where + ": dtype '" + dtype + "' " + kind + " (expected F32, or F16, BF16, F64 converted to F32)");
}

float halfToFloat(uint16_t half) {
  const uint32_t sign = static_cast<uint32_t>(half & 0x8000u) << 16;
  const uint32_t exponent = (half >> 10) & 0x1fu;
  const uint32_t mantissa = half & 0x3ffu;
  if (exponent == 0) {  // zero or subnormal: mantissa * 2^-24
    const float magnitude = std::ldexp(static_cast<float>(mantissa), -24);
    return sign ? -magnitude : magnitude;
  }
  if (exponent == 31) return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));  // inf, NaN
  return std::bit_cast<float>(sign | ((exponent + 112) << 23) | (mantissa << 13));
}

std::vector<float> convert(const std::byte* data, StoredType type, std::size_t count) {
  std::vector<float> values(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::byte* at = data + i * elementBytes(type);
    switch (type) {
      case StoredType::F32: std::memcpy(&values[i], at, 4); break;
      case StoredType::F64: {
        double value;
        std::memcpy(&value, at, 8);
        values[i] = static_cast<float>(value);
        break;
      }
      case StoredType::F16: {
        uint16_t bits;
        std::memcpy(&bits, at, 2);
        values[i] = halfToFloat(bits);
        break;
      }
      case StoredType::BF16: {
        uint16_t bits;
        std::memcpy(&bits, at, 2);
        values[i] = std::bit_cast<float>(static_cast<uint32_t>(bits) << 16);
        break;
      }
    }
  }
  return values;
}

// A JSON number that must be a non-negative integer.
uint64_t natural(const Json& value, const std::string& where) {
  if (value.is_number_unsigned()) return value.get<uint64_t>();
  if (value.is_number_integer() && value.get<int64_t>() >= 0) return static_cast<uint64_t>(value.get<int64_t>());
  throw Error(where + " must be a non-negative integer, got " + value.dump());
}

// Parses the header text, rejecting duplicate keys (which a JSON object would silently collapse).
Json parseHeader(const std::string& text, const std::string& source) {
  if (text.empty() || text.front() != '{') throw fail(source, "the header must be a JSON object starting with '{'");
  std::vector<std::set<std::string>> keysByDepth;
  const Json::parser_callback_t rejectDuplicates = [&](int depth, Json::parse_event_t event, Json& parsed) {
    const auto level = static_cast<std::size_t>(depth);
    if (event == Json::parse_event_t::object_start) {
      if (keysByDepth.size() <= level + 1) keysByDepth.resize(level + 2);
      keysByDepth[level + 1].clear();
    } else if (event == Json::parse_event_t::key) {
      if (keysByDepth.size() <= level) keysByDepth.resize(level + 1);
      const std::string key = parsed.get<std::string>();
      if (!keysByDepth[level].insert(key).second) throw fail(source, "the header names '" + key + "' twice");
    }
    return true;
  };
  try {
    return Json::parse(text, rejectDuplicates);
  } catch (const Json::exception& e) {
    throw fail(source, std::string("the header is not valid JSON: ") + e.what());
  }
}

std::map<std::string, std::string> parseMetadata(const Json& value, const std::string& source) {
  if (!value.is_object()) throw fail(source, "__metadata__ must be an object of strings");
  std::map<std::string, std::string> metadata;
  for (const auto& [key, item] : value.items()) {
    if (!item.is_string()) throw fail(source, "__metadata__ '" + key + "' must be a string, got " + item.dump());
    metadata[key] = item.get<std::string>();
  }
  return metadata;
}

TensorEntry parseEntry(const std::string& name, const Json& value, const std::string& source) {
  const std::string where = source + ": tensor '" + name + "'";
  if (!value.is_object()) throw Error(where + " must be an object with dtype, shape and data_offsets");
  for (const char* field : {"dtype", "shape", "data_offsets"})
    if (!value.contains(field)) throw Error(where + " has no '" + field + "'");
  TensorEntry entry;
  entry.name = name;
  if (!value["dtype"].is_string()) throw Error(where + ": dtype must be a string");
  entry.type = parseDType(value["dtype"].get<std::string>(), where);
  const Json& shape = value["shape"];
  if (!shape.is_array()) throw Error(where + ": shape must be an array of integers");
  for (const Json& extent : shape) {
    const uint64_t dimension = natural(extent, where + ": shape entry");
    if (dimension > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()))
      throw Error(where + ": shape entry " + std::to_string(dimension) + " is too large");
    entry.shape.push_back(static_cast<int64_t>(dimension));
  }
  const Json& offsets = value["data_offsets"];
  if (!offsets.is_array() || offsets.size() != 2) throw Error(where + ": data_offsets must be [begin, end]");
  entry.begin = natural(offsets[0], where + ": data_offsets begin");
  entry.end = natural(offsets[1], where + ": data_offsets end");
  return entry;
}

std::string range(const TensorEntry& entry) {
  return "[" + std::to_string(entry.begin) + ", " + std::to_string(entry.end) + "]";
}

// Offsets inside the data, byte counts that match the shapes, tensors packed without gaps or overlaps.
void checkLayout(std::vector<TensorEntry>& entries, uint64_t dataBytes, const std::string& source) {
  for (const TensorEntry& entry : entries) {
    const std::string where = source + ": tensor '" + entry.name + "'";
    if (entry.begin > entry.end) throw Error(where + ": data_offsets " + range(entry) + " end before they begin");
    if (entry.end > dataBytes)
      throw Error(where + ": data_offsets " + range(entry) + " run past the " + std::to_string(dataBytes) +
                  " data bytes of the file (truncated?)");
    uint64_t bytes = elementBytes(entry.type);
    for (int64_t extent : entry.shape) {
      const auto dimension = static_cast<uint64_t>(extent);
      if (dimension != 0 && bytes > std::numeric_limits<uint64_t>::max() / dimension)
        throw Error(where + ": shape " + toString(entry.shape) + " is too large");
      bytes *= dimension;
    }
    if (bytes != entry.end - entry.begin)
      throw Error(where + ": shape " + toString(entry.shape) + " needs " + std::to_string(bytes) +
                  " bytes but data_offsets " + range(entry) + " span " + std::to_string(entry.end - entry.begin));
  }
  std::stable_sort(entries.begin(), entries.end(),
                   [](const TensorEntry& a, const TensorEntry& b) { return a.begin < b.begin; });
  uint64_t covered = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const TensorEntry& entry = entries[i];
    if (entry.begin < covered)
      throw fail(source, "tensor '" + entry.name + "' data_offsets " + range(entry) + " overlap tensor '" +
                             entries[i - 1].name + "' " + range(entries[i - 1]));
    if (entry.begin > covered)
      throw fail(source, "bytes " + std::to_string(covered) + " to " + std::to_string(entry.begin) +
                             " of the data belong to no tensor (before '" + entry.name + "')");
    covered = entry.end;
  }
  if (covered != dataBytes)
    throw fail(source, std::to_string(dataBytes - covered) + " bytes after the last tensor belong to no tensor");
}

std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
  return text;
}

}  // namespace

const NamedArray* SafetensorsFile::find(const std::string& name) const {
  const auto it = std::find_if(tensors.begin(), tensors.end(), [&](const NamedArray& t) { return t.name == name; });
  return it == tensors.end() ? nullptr : &*it;
}

SafetensorsFile parseSafetensors(std::span<const std::byte> bytes, const std::string& source) {
  if (bytes.size() < 8)
    throw fail(source, "the file is " + std::to_string(bytes.size()) +
                           " bytes long, too short for the 8-byte header length (truncated?)");
  uint64_t headerBytes = 0;
  std::memcpy(&headerBytes, bytes.data(), 8);
  if (headerBytes > bytes.size() - 8)
    throw fail(source, "the header length says " + std::to_string(headerBytes) + " bytes but only " +
                           std::to_string(bytes.size() - 8) + " follow (truncated, or not a .safetensors file)");
  if (headerBytes > kMaxHeaderBytes)
    throw fail(source, "the header length " + std::to_string(headerBytes) + " exceeds the limit of " +
                           std::to_string(kMaxHeaderBytes) + " bytes");
  const std::string text(reinterpret_cast<const char*>(bytes.data() + 8), headerBytes);
  const Json header = parseHeader(text, source);
  if (!header.is_object()) throw fail(source, "the header must be a JSON object");

  SafetensorsFile file;
  std::vector<TensorEntry> entries;
  for (const auto& [name, value] : header.items()) {
    if (name == kMetadataKey) file.metadata = parseMetadata(value, source);
    else entries.push_back(parseEntry(name, value, source));
  }
  const std::byte* data = bytes.data() + 8 + headerBytes;
  checkLayout(entries, bytes.size() - 8 - headerBytes, source);
  for (const TensorEntry& entry : entries) {
    const auto count = static_cast<std::size_t>((entry.end - entry.begin) / elementBytes(entry.type));
    file.tensors.push_back({entry.name, entry.shape, convert(data + entry.begin, entry.type, count)});
  }
  return file;
}

std::vector<std::byte> serializeSafetensors(const std::vector<NamedArray>& tensors,
                                            const std::map<std::string, std::string>& metadata) {
  nlohmann::ordered_json header = nlohmann::ordered_json::object();
  if (!metadata.empty()) header[kMetadataKey] = metadata;
  std::set<std::string> names;
  uint64_t offset = 0;
  for (const NamedArray& tensor : tensors) {
    if (tensor.name.empty() || tensor.name == kMetadataKey)
      throw Error("safetensors: '" + tensor.name + "' cannot name a tensor");
    if (!names.insert(tensor.name).second) throw Error("safetensors: two tensors are named '" + tensor.name + "'");
    if (static_cast<int64_t>(tensor.values.size()) != numElements(tensor.shape))
      throw Error("safetensors: tensor '" + tensor.name + "' of shape " + toString(tensor.shape) + " holds " +
                  std::to_string(tensor.values.size()) + " values");
    const uint64_t bytes = tensor.values.size() * sizeof(float);
    nlohmann::ordered_json entry = nlohmann::ordered_json::object();
    entry["dtype"] = "F32";
    entry["shape"] = tensor.shape;
    entry["data_offsets"] = {offset, offset + bytes};
    header[tensor.name] = std::move(entry);
    offset += bytes;
  }
  std::string text = header.dump();
  text.append((8 - text.size() % 8) % 8, ' ');  // keeps the data 8-byte aligned
  std::vector<std::byte> out(8 + text.size() + offset);
  const uint64_t headerBytes = text.size();
  std::memcpy(out.data(), &headerBytes, 8);
  std::memcpy(out.data() + 8, text.data(), text.size());
  std::byte* data = out.data() + 8 + text.size();
  for (const NamedArray& tensor : tensors) {
    if (!tensor.values.empty()) std::memcpy(data, tensor.values.data(), tensor.values.size() * sizeof(float));
    data += tensor.values.size() * sizeof(float);
  }
  return out;
}

SafetensorsFile readSafetensors(const std::filesystem::path& path) {
  return parseSafetensors(readFileBytes(path), path.string());
}

void writeSafetensors(const std::filesystem::path& path, const std::vector<NamedArray>& tensors,
                      const std::map<std::string, std::string>& metadata) {
  writeFileAtomically(path, serializeSafetensors(tensors, metadata));
}

std::vector<NamedArray> downloadNamed(const std::vector<std::pair<std::string, Tensor>>& tensors) {
  std::vector<NamedArray> arrays;
  arrays.reserve(tensors.size());
  for (const auto& [name, tensor] : tensors) arrays.push_back({name, tensor.shape(), tensor.download()});
  return arrays;
}

void uploadNamed(const SafetensorsFile& file, const std::vector<std::pair<std::string, Tensor>>& targets,
                 const std::string& source, bool strict) {
  std::unordered_map<std::string, const NamedArray*> stored;
  for (const NamedArray& tensor : file.tensors) stored[tensor.name] = &tensor;
  std::vector<std::string> missing, unexpected, differing;
  std::set<std::string> wanted;
  for (const auto& [name, tensor] : targets) {
    wanted.insert(name);
    const auto it = stored.find(name);
    if (it == stored.end()) missing.push_back(name);
    else if (it->second->shape != tensor.shape())
      differing.push_back(name + " (expected " + toString(tensor.shape()) + ", file has " +
                          toString(it->second->shape) + ")");
  }
  for (const NamedArray& tensor : file.tensors)
    if (!wanted.count(tensor.name)) unexpected.push_back(tensor.name);
  if (!strict) {
    missing.clear();
    unexpected.clear();
  }
  if (!missing.empty() || !unexpected.empty() || !differing.empty()) {
    std::vector<std::string> parts;
    if (!missing.empty()) parts.push_back(std::to_string(missing.size()) + " missing: " + joined(missing));
    if (!unexpected.empty())
      parts.push_back(std::to_string(unexpected.size()) + " unexpected: " + joined(unexpected));
    if (!differing.empty())
      parts.push_back(std::to_string(differing.size()) + " with a different shape: " + joined(differing));
    std::string message = source + " does not match the model's tensors; ";
    for (std::size_t i = 0; i < parts.size(); ++i) message += (i ? "; " : "") + parts[i];
    throw Error(message);
  }
  for (const auto& [name, tensor] : targets) {
    const auto it = stored.find(name);
    if (it != stored.end()) tensor.upload(it->second->values);
  }
}

}  // namespace smokesvd::io

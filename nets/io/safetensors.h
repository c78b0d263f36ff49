// .safetensors files: the weight format shared with PyTorch (and most of its ecosystem).
//
// Layout: an 8-byte little-endian unsigned header length N, then N bytes of a UTF-8 JSON object, then
// the data. The JSON maps each tensor name to {"dtype", "shape", "data_offsets": [begin, end]} (byte
// offsets into the data, which starts right after the header); the optional key "__metadata__" maps
// to an object of string values. The data is little-endian, C order, with the tensors packed back to
// back: no gaps, no overlaps, nothing after the last one.
//
// Reading accepts F32 and converts F16, BF16 and F64 to float32; any other dtype is an Error naming
// the tensor. Every inconsistency (a header length past the end of the file, broken JSON, a duplicate
// name, offsets out of range, overlapping or leaving gaps, a byte count that disagrees with the shape)
// is an Error naming the file, the tensor and what was expected. Writing produces F32 and goes
// through "<path>.tmp" renamed into place, so an interrupted write leaves no partial file.
// See docs/file-formats.md.
#pragma once

#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "runtime/tensor.h"

namespace smokesvd::io {

// One tensor on the host, as float32.
struct NamedArray {
  std::string name;
  Shape shape;
  std::vector<float> values;
};

struct SafetensorsFile {
  std::vector<NamedArray> tensors;              // in the order of their data in the file
  std::map<std::string, std::string> metadata;  // the "__metadata__" object (empty if absent)

  const NamedArray* find(const std::string& name) const;  // nullptr when absent
};

// Parses the bytes of a .safetensors file; `source` names it in errors.
SafetensorsFile parseSafetensors(std::span<const std::byte> bytes, const std::string& source);
// Serialises `tensors` as F32 in the given order (names must be unique and non-empty).
std::vector<std::byte> serializeSafetensors(const std::vector<NamedArray>& tensors,
                                            const std::map<std::string, std::string>& metadata = {});

SafetensorsFile readSafetensors(const std::filesystem::path& path);
void writeSafetensors(const std::filesystem::path& path, const std::vector<NamedArray>& tensors,
                      const std::map<std::string, std::string>& metadata = {});

// GPU tensors to and from named host arrays.
std::vector<NamedArray> downloadNamed(const std::vector<std::pair<std::string, Tensor>>& tensors);
// Uploads the file's tensors into `targets` (name -> tensor), like PyTorch's load_state_dict. Strict: every
// target must be in the file with its exact shape and the file must hold nothing else. Not strict: targets
// absent from the file keep their values and extra tensors in the file are ignored, but shapes must still
// agree. On any mismatch nothing is uploaded and the Error lists every one: missing names, unexpected
// names, and shapes that differ.
void uploadNamed(const SafetensorsFile& file, const std::vector<std::pair<std::string, Tensor>>& targets,
                 const std::string& source, bool strict = true);

}  // namespace smokesvd::io

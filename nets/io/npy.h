// NumPy .npy and .npz files (format version 1.0/2.0/3.0), the volume and array format of smokesvd.
//
// Supported element types: float32 ('<f4') and int32 ('<i4'), C order. Anything else (another dtype,
// big-endian data, Fortran order, a header that disagrees with the file's size) is an Error naming the
// file, the field and what was expected. Writes go to "<path>.tmp" and are renamed into place, so an
// interrupted write never leaves a half-written file under the real name.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "runtime/tensor.h"

namespace smokesvd::io {

enum class DType { Float32, Int32 };

struct NpyArray {
  Shape shape;
  DType dtype = DType::Float32;
  std::vector<float> floats;    // when dtype == Float32
  std::vector<int32_t> ints;    // when dtype == Int32

  int64_t numel() const { return numElements(shape); }
  // The values as float32 (int32 converted); what GPU tensors are made from.
  std::vector<float> toFloat() const;

  static NpyArray fromFloats(Shape shape, std::vector<float> values);
  static NpyArray fromInts(Shape shape, std::vector<int32_t> values);
};

// Parses the bytes of one .npy file; `source` names it in errors (e.g. "a.npz:density.npy").
NpyArray parseNpy(std::span<const std::byte> bytes, const std::string& source);
std::vector<std::byte> serializeNpy(const NpyArray& array);

NpyArray readNpy(const std::filesystem::path& path);
void writeNpy(const std::filesystem::path& path, const NpyArray& array);

// .npz: a zip of .npy members; keys are member names without ".npy". Stored and deflated members are read.
std::map<std::string, NpyArray> readNpz(const std::filesystem::path& path);
// One member of an .npz; throws Error listing the available keys if `key` is missing.
NpyArray readNpzMember(const std::filesystem::path& path, const std::string& key);
void writeNpz(const std::filesystem::path& path, const std::map<std::string, NpyArray>& arrays, bool compress = true);

}  // namespace smokesvd::io

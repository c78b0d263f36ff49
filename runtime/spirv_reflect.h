// Reads from a compute shader's SPIR-V what the host must agree with: the descriptor bindings of
// set 0 (kind, and whether the shader reads and/or writes each) and whether it has push constants.
// Kernels therefore never restate their interface in C++.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace smokesvd {

enum class BindingKind {
  StorageBuffer,       // `buffer` block: read and/or written
  UniformTexelBuffer,  // `samplerBuffer` / `textureBuffer`: read through texelFetch
};

struct BindingInfo {
  uint32_t binding = 0;
  BindingKind kind = BindingKind::StorageBuffer;
  bool reads = true;
  bool writes = false;
  // Whether the block holds floats meant to be finite, which the finite check scans (runtime/finite_check.h):
  // false for blocks of signed integers (`int`) and for blocks named *NonFinite (±Inf on purpose).
  bool finiteFloats = true;
  std::string name;  // the GLSL variable or block name, for errors
};

struct ShaderInterface {
  std::vector<BindingInfo> bindings;  // sorted by binding, numbered 0..n-1 without gaps
  bool hasPushConstants = false;
  std::vector<uint32_t> specializationIds;
};

// Throws Error naming `shaderName` if the module is malformed or uses an unsupported binding.
ShaderInterface reflectShader(std::span<const uint32_t> spirv, const std::string& shaderName);

}  // namespace smokesvd

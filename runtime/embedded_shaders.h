// The SPIR-V of every shader under shaders/, compiled and embedded at build time (shaders/CMakeLists.txt).
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>

namespace smokesvd {

// Keyed by the shader's path under shaders/ without ".comp", e.g. "tensor/fill".
const std::map<std::string, std::span<const uint32_t>, std::less<>>& embeddedShaders();

}  // namespace smokesvd

#include "pipeline/preset.h"

#include "runtime/error.h"

namespace smokesvd {

const std::vector<Preset>& presets() {
  static const std::vector<Preset> all = {
      {"tiny", {.x = 16, .y = 28, .z = 16}, 16, 28, 16, 8, 1.2f},
      {"small", {.x = 32, .y = 56, .z = 32}, 32, 56, 16, 60, 0.6f},
      {"paper", {.x = 64, .y = 112, .z = 64}, 64, 112, 16, 150, 0.3f},
  };
  return all;
}

const Preset& preset(const std::string& name) {
  for (const Preset& p : presets())
    if (p.name == name) return p;
  throw Error("unknown preset '" + name + "'; expected one of: tiny, small, paper");
}

}  // namespace smokesvd

// The default network configs of every preset, models/configs/<preset>/<network>.json, embedded at build
// time (CMakeLists.txt generates the table). Keys are "<preset>/<network>", values the files' text.
#pragma once

#include <map>
#include <string>
#include <string_view>

namespace smokesvd::networks {

const std::map<std::string, std::string_view>& embeddedConfigs();

}  // namespace smokesvd::networks

// A module's weights as a .safetensors file with PyTorch's names and layouts (model.state_dict() keys;
// conv weight [out, in, k...], linear [out, in]), so a file written here loads with
// model.load_state_dict(safetensors.torch.load_file(path)) and the other way round.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "nets/io/safetensors.h"
#include "nets/modules/module.h"

namespace smokesvd::modules {

void saveWeights(const std::filesystem::path& path, const Module& module,
                 const std::map<std::string, std::string>& metadata = {});
// Loads every parameter by name. Strict (the default, like load_state_dict): the file must hold exactly
// the module's parameters with their shapes; otherwise nothing is loaded and the Error lists every
// missing name, unexpected name and differing shape. Not strict: absent parameters keep their values and
// extra tensors are ignored; shapes must still agree. Returns the file's metadata.
std::map<std::string, std::string> loadWeights(const std::filesystem::path& path, Module& module, bool strict = true);
// The same from a file already read; `source` names it in errors.
void loadWeights(const io::SafetensorsFile& file, Module& module, const std::string& source, bool strict = true);

}  // namespace smokesvd::modules

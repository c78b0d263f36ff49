#include "nets/modules/weights.h"

#include "nets/io/safetensors.h"

namespace smokesvd::modules {
namespace {

std::vector<std::pair<std::string, Tensor>> namedValues(const Module& module) {
  std::vector<std::pair<std::string, Tensor>> values;
  for (const auto& [name, parameter] : module.namedParameters()) values.emplace_back(name, parameter->value);
  return values;
}

}  // namespace

void saveWeights(const std::filesystem::path& path, const Module& module,
                 const std::map<std::string, std::string>& metadata) {
  io::writeSafetensors(path, io::downloadNamed(namedValues(module)), metadata);
}

std::map<std::string, std::string> loadWeights(const std::filesystem::path& path, Module& module, bool strict) {
  const io::SafetensorsFile file = io::readSafetensors(path);
  loadWeights(file, module, path.string(), strict);
  return file.metadata;
}

void loadWeights(const io::SafetensorsFile& file, Module& module, const std::string& source, bool strict) {
  io::uploadNamed(file, namedValues(module), source, strict);
}

}  // namespace smokesvd::modules

#include "nets/optim/checkpoint.h"

#include <sstream>

#include "nets/io/safetensors.h"
#include "runtime/error.h"

namespace smokesvd::optim {
namespace {

const std::string kFormat = "smokesvd-checkpoint";
const std::string kFormatVersion = "1";

using NamedTensors = std::vector<std::pair<std::string, Tensor>>;

std::string kindOf(const Adam& adam) { return adam.options().decoupledWeightDecay ? "adamw" : "adam"; }

std::string number(double value) {
  std::ostringstream text;
  text.precision(17);
  text << value;
  return text.str();
}

// What a checkpoint holds: the model's tensors themselves, copies of the optimiser's state and the EMA's
// shadows (restored from the copies after a load).
struct Contents {
  NamedTensors state, shadows;
  NamedTensors all;
};

Contents everything(const NamedParameters& model, const Adam& adam, const Ema* ema) {
  Contents contents{adam.namedState(), ema ? ema->namedShadows() : NamedTensors{}, {}};
  for (const auto& [name, parameter] : model) contents.all.emplace_back(name, parameter->value);
  for (const auto& [name, tensor] : contents.state) contents.all.emplace_back("optimizer." + name, tensor);
  for (const auto& [name, tensor] : contents.shadows) contents.all.emplace_back("ema." + name, tensor);
  return contents;
}

std::string required(const std::map<std::string, std::string>& metadata, const std::string& key,
                     const std::string& source) {
  const auto it = metadata.find(key);
  if (it == metadata.end()) throw Error(source + ": checkpoint metadata has no '" + key + "'");
  return it->second;
}

}  // namespace

void saveCheckpoint(const std::filesystem::path& path, const NamedParameters& model, const Adam& adam, const Ema* ema,
                    const std::map<std::string, std::string>& metadata) {
  std::map<std::string, std::string> all = metadata;
  const AdamOptions& options = adam.options();
  all["format"] = kFormat;
  all["format_version"] = kFormatVersion;
  all["optimizer"] = kindOf(adam);
  all["step"] = std::to_string(adam.steps());
  all["lr"] = number(adam.lastLearningRate());
  all["beta1"] = number(options.beta1);
  all["beta2"] = number(options.beta2);
  all["eps"] = number(options.eps);
  all["weight_decay"] = number(options.weightDecay);
  io::writeSafetensors(path, io::downloadNamed(everything(model, adam, ema).all), all);
}

std::map<std::string, std::string> loadCheckpoint(const std::filesystem::path& path, const NamedParameters& model,
                                                  Adam& adam, Ema* ema) {
  const std::string source = path.string();
  const io::SafetensorsFile file = io::readSafetensors(path);
  if (file.metadata.count("format") == 0 || file.metadata.at("format") != kFormat)
    throw Error(source + ": not a training checkpoint (metadata 'format' is not '" + kFormat + "')");
  if (required(file.metadata, "format_version", source) != kFormatVersion)
    throw Error(source + ": checkpoint format version " + file.metadata.at("format_version") + ", expected " +
                kFormatVersion);
  const std::string kind = required(file.metadata, "optimizer", source);
  if (kind != kindOf(adam))
    throw Error(source + ": the checkpoint holds " + kind + " state but the optimiser is " + kindOf(adam));
  const std::string stepText = required(file.metadata, "step", source);
  int64_t step = 0;
  try {
    std::size_t used = 0;
    step = std::stoll(stepText, &used);
    if (used != stepText.size() || step < 0 || step > Adam::kMaxSteps) throw std::invalid_argument(stepText);
  } catch (const std::logic_error&) {
    throw Error(source + ": checkpoint metadata 'step' is '" + stepText + "', not a step count in [0, 2^24]");
  }
  const Contents contents = everything(model, adam, ema);
  io::uploadNamed(file, contents.all, source);
  adam.restoreState(contents.state);
  if (ema) ema->restoreShadows(contents.shadows);
  adam.setSteps(step);
  return file.metadata;
}

bool isCheckpoint(const io::SafetensorsFile& file) {
  const auto format = file.metadata.find("format");
  return format != file.metadata.end() && format->second == kFormat;
}

io::SafetensorsFile checkpointEmaWeights(const io::SafetensorsFile& file, const std::string& source) {
  const std::string prefix = "ema.";
  io::SafetensorsFile weights{{}, file.metadata};
  for (const io::NamedArray& tensor : file.tensors)
    if (tensor.name.starts_with(prefix)) weights.tensors.push_back({tensor.name.substr(prefix.size()), tensor.shape, tensor.values});
  if (weights.tensors.empty()) throw Error(source + ": the checkpoint holds no EMA weights (no 'ema.' tensors)");
  return weights;
}

}  // namespace smokesvd::optim

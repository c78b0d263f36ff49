#include "pipeline/reconstruct/method_models.h"

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "nets/io/file_io.h"
#include "nets/models/model_json.h"
#include "pipeline/networks/trained_model.h"
#include "runtime/error.h"

namespace smokesvd::reconstruct {
namespace {

using networks::Network;

std::string fileHash(const std::filesystem::path& path) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (const std::byte b : io::readFileBytes(path)) {
    hash ^= static_cast<uint64_t>(b);
    hash *= 0x100000001b3ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace

MethodModels::MethodModels(Context& context, const std::filesystem::path& folder, const Preset& preset, bool sideViews) {
  if (!std::filesystem::is_directory(folder))
    throw Error(folder.string() + ": no models folder (train the networks with `smokesvd train`, or give --models)");
  auto load = [&](Network n, modules::Module& module, const networks::TrainedModel& trained) {
    networks::loadTrainedWeights(trained, module);
    hashes[networks::networkName(n)] = fileHash(trained.weights);
  };
  auto unet3 = [](const networks::TrainedModel& t) { return models::unet3PlusFromJson(t.config.model, t.config.source + " [model]"); };

  std::vector<modules::Module*> modules;
  if (sideViews) {
    const auto sv = networks::findTrainedModel(folder, Network::SvDiff, preset);
    sideView = networks::makeSideViewSynthesizer(context, sv.config);
    load(Network::SvDiff, sideView->net(), sv);
    schedule = networks::diffusionSettings(sv.config).schedule;
    const auto svi = networks::findTrainedModel(folder, Network::SvDiffInit, preset);
    sideViewInit = networks::makeSideViewSynthesizer(context, svi.config);
    load(Network::SvDiffInit, sideViewInit->net(), svi);
    initSchedule = networks::diffusionSettings(svi.config).schedule;
    modules = {&sideView->net(), &sideViewInit->net()};
  }
  const auto gc = networks::findTrainedModel(folder, Network::GrhoCoarse, preset);
  coarse = std::make_unique<networks::DensityGenerator>(context, unet3(gc), preset);
  load(Network::GrhoCoarse, coarse->net(), gc);
  const auto gf = networks::findTrainedModel(folder, Network::GrhoFine, preset);
  fine = std::make_unique<networks::DensityGenerator>(context, unet3(gf), preset);
  load(Network::GrhoFine, fine->net(), gf);
  const auto nv = networks::findTrainedModel(folder, Network::NvRef, preset);
  refiner = std::make_unique<networks::Refiner>(context, unet3(nv));
  load(Network::NvRef, refiner->net(), nv);
  refinerBeta = networks::number(nv.config.options, "beta", nv.config.source + " [options]");
  const auto gu = networks::findTrainedModel(folder, Network::Gu, preset);
  velocity = std::make_unique<networks::VelocityGenerator>(context, unet3(gu), preset);
  load(Network::Gu, velocity->net(), gu);
  modules.insert(modules.end(), {&coarse->net(), &fine->net(), &refiner->net(), &velocity->net()});
  for (modules::Module* m : modules) {
    m->setTraining(false);
    networks::freeze(*m);
  }
}

std::filesystem::path defaultModelsFolder(const std::string& preset) {
  if (const char* override = std::getenv("SMOKESVD_MODELS")) return std::filesystem::path(override) / preset;
  return std::filesystem::path(SMOKESVD_PROJECT_DIR) / "models" / preset;
}

}  // namespace smokesvd::reconstruct

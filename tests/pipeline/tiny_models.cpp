#include "tests/pipeline/tiny_models.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "nets/io/temporary_folder.h"
#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "pipeline/train/make_trainer.h"
#include "pipeline/train/training_run.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

class FileLock {
 public:
  explicit FileLock(const fs::path& path) : fd_(::open(path.c_str(), O_CREAT | O_RDWR, 0644)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0) throw Error(path.string() + ": cannot lock");
  }
  ~FileLock() {
    ::flock(fd_, LOCK_UN);
    ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

// build/tests-cache/tiny-<build time of this test program>/
fs::path cacheFolder() {
  struct stat info{};
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  ::stat(self.c_str(), &info);
  return fs::path(SMOKESVD_SMOKESVD_BINARY).parent_path() / "tests-cache" /
         ("tiny-" + fs::path(self).filename().string() + "-" + std::to_string(info.st_mtime));
}

void makeDataset(const fs::path& root) {
  for (int i = 0; i < 4; ++i) {
    sim::Scene scene = sim::randomScene(100 + static_cast<uint64_t>(i), preset("tiny").grid, 8);
    scene.render.enabled = false;
    sim::runScene(testContext(), scene, root / ("scene_000" + std::to_string(i)), {});
  }
}

void trainModels(const fs::path& data, const fs::path& models) {
  dataset::DatasetOptions options;
  options.validationEvery = 4;
  const dataset::SceneDataset dataset(data, preset("tiny"), options);
  for (const networks::Network n : networks::allNetworks()) {
    networks::NetworkConfig c = networks::defaultNetworkConfig("tiny", n);
    c.train.steps = 6;
    c.train.warmup = 1;
    c.train.logEvery = 1;
    c.train.checkpointEvery = 3;
    c.train.validateEvery = 6;
    c.train.validationSamples = 1;
    c.data.validationEvery = 4;
    if (n == networks::Network::Gu) c.options["finetune_steps"] = 2;
    const auto trainer = train::makeTrainer(testContext(), c, dataset, models);
    train::TrainingOptions o;
    o.out = models / networks::networkName(n);
    o.quiet = true;
    o.overwrite = true;
    train::runTraining(testContext(), *trainer, c, o);
  }
}

const fs::path& ready() {
  static const fs::path root = [] {
    const fs::path folder = cacheFolder();
    fs::create_directories(folder.parent_path());
    FileLock lock(folder.parent_path() / "tiny.lock");
    if (!fs::exists(folder / "complete")) {
      fs::remove_all(folder);
      makeDataset(folder / "data");
      trainModels(folder / "data", folder / "models");
      std::ofstream(folder / "complete") << "ok\n";
    }
    return folder;
  }();
  return root;
}

}  // namespace

const fs::path& tinyDataset() {
  static const fs::path data = ready() / "data";
  return data;
}

const fs::path& tinyModels() {
  static const fs::path models = ready() / "models";
  return models;
}

fs::path tinyScratch(const std::string& name) {
  static const io::TemporaryFolder root("pipeline");
  const fs::path path = root / name;
  fs::remove_all(path);
  fs::create_directories(path);
  return path;
}

}  // namespace smokesvd::testing

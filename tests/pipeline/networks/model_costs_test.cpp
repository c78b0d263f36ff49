#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "nets/models/model_json.h"
#include "nets/modules/flop_counter.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/preset.h"
#include "tests/harness/gpu_test.h"

namespace smokesvd::testing {
namespace {

// The parameter counts and forward GFLOP of every network at every preset (batch 1: one volume, one
// image, one denoising step), counted by Module::parameterCount and modules::FlopCounter, must be the
// table of docs/models.md. A paper-preset tensor can be larger than one lavapipe buffer may span, so
// forwards are counted at two small sizes and extended exactly: every convolution's output has
// (volume / 2^(d l)) positions at level l when every spatial size is divisible by 2^(L-1), so
// FLOPs = a * volume + b (b: the linear layers, once per sample). At the tiny and small presets the
// extension is checked against a forward at the preset's own size.

using networks::Network;

struct Architecture {
  std::unique_ptr<modules::Module> module;
  std::function<void(Tape&, const std::vector<int64_t>&)> forward;  // at spatial sizes (D, H, W) or (H, W)
  std::vector<int64_t> presetSize;
  int levels = 0;
};

Architecture build(Context& context, const networks::NetworkConfig& config) {
  const Preset& p = preset(config.preset);
  const std::string where = config.source + " [model]";
  Architecture a;
  auto shaped = [](int64_t n, int64_t channels, const std::vector<int64_t>& spatial) {
    Shape shape{n, channels};
    shape.insert(shape.end(), spatial.begin(), spatial.end());
    return shape;
  };
  if (config.model.at("architecture") == "unet3plus") {
    const models::UNet3PlusConfig c = models::unet3PlusFromJson(config.model, where);
    auto net = std::make_unique<models::UNet3Plus>(context, c);
    a.forward = [&context, c, shaped, raw = net.get()](Tape& tape, const std::vector<int64_t>& spatial) {
      const Var presence = c.presenceSlots > 0 ? variable(Tensor(context, {1, c.presenceSlots})) : nullptr;
      raw->forward(tape, variable(Tensor(context, shaped(1, c.inChannels, spatial))), presence);
    };
    a.presetSize = c.dims == 3 ? std::vector<int64_t>{p.grid.z, p.grid.y, p.grid.x}
                               : std::vector<int64_t>{p.imageHeight, p.imageWidth};
    a.levels = c.levels();
    a.module = std::move(net);
  } else {
    const models::DdpmUNetConfig c = models::ddpmUNetFromJson(config.model, where);
    auto net = std::make_unique<models::DdpmUNet>(context, c);
    a.forward = [&context, c, shaped, raw = net.get()](Tape& tape, const std::vector<int64_t>& spatial) {
      raw->forward(tape, variable(Tensor(context, shaped(1, c.inChannels, spatial))), variable(Tensor(context, {1})));
    };
    a.presetSize = {p.imageHeight, p.imageWidth};
    a.levels = c.levels();
    a.module = std::move(net);
  }
  return a;
}

double countFlops(Context& context, const Architecture& a, const std::vector<int64_t>& spatial) {
  Stream stream(context);
  Tape tape(stream);
  NoGrad noGrad(tape);
  modules::FlopCounter counter;
  a.forward(tape, spatial);
  return counter.flops();
}

double positions(const std::vector<int64_t>& spatial) {
  double n = 1;
  for (const int64_t s : spatial) n *= static_cast<double>(s);
  return n;
}

std::string withThousands(int64_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string threeDigits(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

class ModelCostTest : public GpuTest {};

TEST_F(ModelCostTest, DocsTableHoldsEveryNetworksParametersAndForwardGflop) {
  const std::vector<std::string> presets{"tiny", "small", "paper"};
  std::ostringstream table;
  table << "| network | tiny: parameters | GFLOP | small: parameters | GFLOP | paper: parameters | GFLOP |\n"
        << "|---|---:|---:|---:|---:|---:|---:|\n";
  for (const Network network : networks::allNetworks()) {
    table << "| " << networks::networkName(network);
    for (const std::string& name : presets) {
      const Architecture a = build(context(), networks::defaultNetworkConfig(name, network));
      const std::vector<int64_t> small(a.presetSize.size(), int64_t{1} << (a.levels - 1));
      std::vector<int64_t> wider = small;
      wider.back() *= 2;
      const double f1 = countFlops(context(), a, small), f2 = countFlops(context(), a, wider);
      const double perPosition = (f2 - f1) / (positions(wider) - positions(small));
      const double flops = f1 + perPosition * (positions(a.presetSize) - positions(small));
      if (name != "paper") {
        EXPECT_NEAR(flops, countFlops(context(), a, a.presetSize), 1e-12 * flops)
            << networks::networkName(network) << " " << name;
      }
      table << " | " << withThousands(a.module->parameterCount()) << " | " << threeDigits(flops * 1e-9);
    }
    table << " |\n";
  }
  std::ifstream file(SMOKESVD_SOURCE_DIR "/docs/models.md");
  std::stringstream docs;
  docs << file.rdbuf();
  EXPECT_NE(docs.str().find(table.str()), std::string::npos)
      << "docs/models.md should hold this table:\n" << table.str();
}

}  // namespace
}  // namespace smokesvd::testing

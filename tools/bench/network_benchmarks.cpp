#include "tools/bench/network_benchmarks.h"

#include "pipeline/preset.h"

namespace smokesvd::bench {

bool registerNetworkBenchmarks(const std::string& group, NetworkMeasure measure) {
  for (const networks::Network network : networks::allNetworks())
    for (const Preset& p : presets()) {
      const std::string name = group + "/" + networks::networkName(network) + "/" + p.name;
      registerBenchmark({name, [measure, name, network, presetName = p.name](BenchContext& b) {
                           measure(b, name, network, presetName);
                         }});
    }
  return true;
}

}  // namespace smokesvd::bench

// Benchmarks of every network at every preset (network_training_benchmarks.cpp, network_inference_benchmarks.cpp):
// one registration loop for both.
#pragma once

#include <string>

#include "pipeline/networks/network_config.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {

// Measures the benchmark `name` of `network` at the preset `presetName`.
using NetworkMeasure = void (*)(BenchContext& b, const std::string& name, networks::Network network,
                                const std::string& presetName);

// Registers <group>/<network>/<preset> for every network (networks::allNetworks) at every preset (presets()).
bool registerNetworkBenchmarks(const std::string& group, NetworkMeasure measure);

}  // namespace smokesvd::bench

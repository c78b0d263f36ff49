// `smokesvd bench [FILTER] [--json]`: times kernels with GPU timestamps (warm-up, then the median of
// many runs) and prints kernel, shape, median time, GB/s or GFLOP/s, and the device.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "runtime/error.h"
#include "tools/bench/bench.h"
#include "tools/smokesvd/command.h"

namespace smokesvd::cli {
namespace {

struct BenchArguments {
  std::string filter;
  bool json = false;
  bool list = false;
  bench::BenchOptions options;
};

void printTable(const std::vector<bench::Measurement>& results) {
  std::printf("%-34s %-34s %12s %10s %10s\n", "kernel", "shape", "median", "GB/s", "GFLOP/s");
  for (const bench::Measurement& m : results) {
    const double micros = m.medianNs / 1000.0;
    char gb[32] = "-", gflop[32] = "-";
    if (m.bytes > 0) std::snprintf(gb, sizeof gb, "%.2f", m.gbPerSecond());
    if (m.flops > 0) std::snprintf(gflop, sizeof gflop, "%.2f", m.gflopPerSecond());
    std::printf("%-34s %-34s %9.1f us %10s %10s\n", m.name.c_str(), m.shape.c_str(), micros, gb, gflop);
  }
}

void addBenchCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static BenchArguments args;
  CLI::App* command = app.add_subcommand("bench", "time kernels on the device (GPU timestamps, median of runs)");
  command->add_option("filter", args.filter, "run only benchmarks whose name contains this text");
  command->add_flag("--json", args.json, "print JSON");
  command->add_flag("--list", args.list, "list benchmark names and exit");
  command->add_option("--runs", args.options.runs, "timed runs per kernel (median is reported)")->check(CLI::PositiveNumber);
  command->add_option("--warmup", args.options.warmup, "untimed runs before timing")->check(CLI::NonNegativeNumber);
  command->callback([&global, &action] {
    action = [&global] {
      if (args.list) {
        for (const bench::Benchmark& b : bench::benchmarks()) std::cout << b.name << "\n";
        return;
      }
      Context context(global.contextOptions());
      bench::BenchContext bench(context, args.options);
      int matched = 0;
      if (!args.json) std::cout << "device: " << context.info().name << " (" << context.info().driver << ")\n";
      for (const bench::Benchmark& b : bench::benchmarks()) {
        if (b.name.find(args.filter) == std::string::npos) continue;
        ++matched;
        const std::size_t before = bench.results().size();
        b.run(bench);
        if (!args.json)
          printTable({bench.results().begin() + static_cast<std::ptrdiff_t>(before), bench.results().end()});
      }
      if (matched == 0) throw Error("bench: no benchmark matches '" + args.filter + "' (see smokesvd bench --list)");
      if (args.json) {
        nlohmann::json results = nlohmann::json::array();
        for (const bench::Measurement& m : bench.results()) {
          results.push_back({{"kernel", m.name}, {"shape", m.shape}, {"median_ns", m.medianNs}, {"runs", m.runs},
                             {"bytes", m.bytes}, {"flops", m.flops}, {"gb_per_s", m.gbPerSecond()},
                             {"gflop_per_s", m.gflopPerSecond()}});
        }
        std::cout << nlohmann::json{{"device", context.info().name}, {"driver", context.info().driver},
                                    {"device_type", context.info().typeName()}, {"results", results}}
                         .dump(2)
                  << "\n";
      }
    };
  });
}

const bool registered = registerCommand({"bench", addBenchCommand});

}  // namespace
}  // namespace smokesvd::cli

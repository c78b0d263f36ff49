// `smokesvd bench [FILTER] [--json]`: times kernels with GPU timestamps (warm-up, then the median of
// many runs) and prints kernel, shape, median time, GB/s or GFLOP/s, and the device. It first measures
// the device's reference figures (loop-FMA peak, best kernel copy bandwidth) and gives every figure also
// as a percentage of its reference, which stays comparable across machines and moments.
#include <cstdio>
#include <iostream>
#include <string>
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
  bool reference = true;
  bench::BenchOptions options;
};

// "12.3" of `value`, "-" when there is none.
std::string figure(double value, const char* format = "%.2f") {
  if (value <= 0) return "-";
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

double percent(double value, double reference) { return reference > 0 ? 100.0 * value / reference : 0; }

void printTable(const std::vector<bench::Measurement>& results, const bench::DeviceReference& reference) {
  std::printf("%-36s %-36s %12s %9s %6s %9s %6s\n", "kernel", "shape", "median", "GB/s", "%copy", "GFLOP/s", "%peak");
  for (const bench::Measurement& m : results) {
    std::printf("%-36s %-36s %9.1f us %9s %6s %9s %6s\n", m.name.c_str(), m.shape.c_str(), m.medianNs / 1000.0,
                figure(m.gbPerSecond()).c_str(), figure(percent(m.gbPerSecond(), reference.bandwidthGbps), "%.0f").c_str(),
                figure(m.gflopPerSecond()).c_str(),
                figure(percent(m.gflopPerSecond(), reference.peakGflops), "%.0f").c_str());
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
  command->add_flag("!--no-reference", args.reference,
                    "skip measuring the reference figures (loop-FMA peak, copy bandwidth) and the % columns");
  command->callback([&global, &action] {
    action = [&global] {
      if (args.list) {
        for (const bench::Benchmark& b : bench::benchmarks()) std::cout << b.name << "\n";
        return;
      }
      std::vector<const bench::Benchmark*> selected;
      for (const bench::Benchmark& b : bench::benchmarks())
        if (b.name.find(args.filter) != std::string::npos) selected.push_back(&b);
      if (selected.empty()) throw Error("bench: no benchmark matches '" + args.filter + "' (see smokesvd bench --list)");
      Context context(global.contextOptions());
      bench::BenchContext bench(context, args.options);
      if (!args.json) std::cout << "device: " << context.info().name << " (" << context.info().driver << ")\n";
      // The reference is measured before and after the benchmarks and averaged: on a shared machine the
      // speed drifts during a long run, and a single reading would skew every percentage.
      const bench::DeviceReference before =
          args.reference ? bench::measureDeviceReference(context, args.options) : bench::DeviceReference{};
      std::vector<std::vector<bench::Measurement>> groups;
      for (const bench::Benchmark* b : selected) {
        const std::size_t first = bench.results().size();
        b->run(bench);
        groups.emplace_back(bench.results().begin() + static_cast<std::ptrdiff_t>(first), bench.results().end());
      }
      const bench::DeviceReference after =
          args.reference ? bench::measureDeviceReference(context, args.options) : bench::DeviceReference{};
      const bench::DeviceReference reference{(before.peakGflops + after.peakGflops) / 2,
                                             (before.bandwidthGbps + after.bandwidthGbps) / 2};
      if (!args.json) {
        if (args.reference)
          std::printf("reference (mean of before/after): loop-FMA peak %.2f GFLOP/s (%.2f/%.2f), kernel copy %.2f GB/s "
                      "(%.2f/%.2f)\n",
                      reference.peakGflops, before.peakGflops, after.peakGflops, reference.bandwidthGbps,
                      before.bandwidthGbps, after.bandwidthGbps);
        for (const std::vector<bench::Measurement>& group : groups) printTable(group, reference);
      }
      if (args.json) {
        nlohmann::json results = nlohmann::json::array();
        for (const bench::Measurement& m : bench.results()) {
          results.push_back({{"kernel", m.name}, {"shape", m.shape}, {"median_ns", m.medianNs}, {"runs", m.runs},
                             {"bytes", m.bytes}, {"flops", m.flops}, {"gb_per_s", m.gbPerSecond()},
                             {"gflop_per_s", m.gflopPerSecond()},
                             {"percent_of_copy", percent(m.gbPerSecond(), reference.bandwidthGbps)},
                             {"percent_of_peak", percent(m.gflopPerSecond(), reference.peakGflops)}});
        }
        std::cout << nlohmann::json{{"device", context.info().name}, {"driver", context.info().driver},
                                    {"device_type", context.info().typeName()},
                                    {"reference", {{"peak_gflop_per_s", reference.peakGflops},
                                                   {"copy_gb_per_s", reference.bandwidthGbps}}},
                                    {"results", results}}
                         .dump(2)
                  << "\n";
      }
    };
  });
}

const bool registered = registerCommand({"bench", addBenchCommand});

}  // namespace
}  // namespace smokesvd::cli

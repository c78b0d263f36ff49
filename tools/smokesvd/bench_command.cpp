// `smokesvd bench [FILTER] [--json]`: times kernels with GPU timestamps (warm-up, then the median of
// many runs) and prints kernel, shape, median time, GB/s or GFLOP/s, and the device. It first measures
// the device's reference figures (loop-FMA peak, best kernel copy bandwidth) and gives every figure also
// as a percentage of its reference, which stays comparable across machines and moments. With --passes N
// the whole selection runs N times and every figure (the references too) keeps its best pass: on a
// shared machine whose speed drifts from minute to minute, that is the figure of its quiet moments.
// Training-step benchmarks also report their memory: what the recording holds, with and without buffer
// reuse, and the pool's peak (docs/runtime.md, "Memory within a recording").
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <nlohmann/json.hpp>

#include "runtime/error.h"
#include "tools/bench/bench.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"

namespace smokesvd::cli {
namespace {

struct BenchArguments {
  std::string filter;
  bool json = false;
  bool list = false;
  bool reference = true;
  int passes = 1;
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

// Each measurement's time per shader, slowest first, as a share of the profiled run (--profile), then its
// slowest dispatches with their grids, constants and push constants (--profile-dispatches).
void printProfiles(const std::vector<bench::Measurement>& results) {
  for (const bench::Measurement& m : results) {
    if (m.profile.shaders.empty()) continue;
    double total = 0;
    int dispatches = 0;
    for (const bench::ProfileLine& line : m.profile.shaders) {
      total += line.nanoseconds;
      dispatches += line.dispatches;
    }
    std::printf("profile of %s: %d dispatches, %.1f us in them (a timed run: %.1f us, CPU %.1f us)\n", m.name.c_str(),
                dispatches, total / 1000.0, m.medianNs / 1000.0, m.medianCpuNs / 1000.0);
    for (const bench::ProfileLine& line : m.profile.shaders)
      std::printf("  %-40s %12.1f us %6d %6.1f %%\n", line.shader.c_str(), line.nanoseconds / 1000.0, line.dispatches,
                  percent(line.nanoseconds, total));
    if (m.profile.dispatches.empty()) continue;
    std::printf("slowest dispatches of %s:\n", m.name.c_str());
    for (const bench::DispatchLine& line : m.profile.dispatches)
      std::printf("  %-40s %12.1f us %6.1f %%  %s\n", line.shader.c_str(), line.nanoseconds / 1000.0,
                  percent(line.nanoseconds, total), line.detail.c_str());
  }
}

void printTable(const std::vector<bench::Measurement>& results, const bench::DeviceReference& reference) {
  std::printf("%-36s %-36s %12s %9s %6s %9s %6s\n", "kernel", "shape", "median", "GB/s", "%copy", "GFLOP/s", "%peak");
  for (const bench::Measurement& m : results) {
    if (!m.notRun.empty()) {
      std::printf("%-36s not run: %s\n", m.name.c_str(), m.notRun.c_str());
      continue;
    }
    std::printf("%-36s %-36s %9.1f us %9s %6s %9s %6s\n", m.name.c_str(), m.shape.c_str(), m.medianNs / 1000.0,
                figure(m.gbPerSecond()).c_str(), figure(percent(m.gbPerSecond(), reference.bandwidthGbps), "%.0f").c_str(),
                figure(m.gflopPerSecond()).c_str(),
                figure(percent(m.gflopPerSecond(), reference.peakGflops), "%.0f").c_str());
  }
}

double mebibytes(uint64_t bytes) { return static_cast<double>(bytes) / (1 << 20); }

// The memory of the training steps (BenchContext::measureStep), after the tables.
void printMemory(const std::vector<std::vector<bench::Measurement>>& groups) {
  bool header = false;
  for (const std::vector<bench::Measurement>& group : groups) {
    for (const bench::Measurement& m : group) {
      if (m.heldBytes == 0) continue;
      if (!header) std::printf("\n%-36s %14s %16s %14s\n", "memory of a recorded step", "held", "without reuse",
                               "pool peak");
      header = true;
      std::printf("%-36s %10.1f MiB %12.1f MiB %10.1f MiB\n", m.name.c_str(), mebibytes(m.heldBytes),
                  mebibytes(m.heldBytesWithoutReuse), mebibytes(m.poolPeakBytes));
    }
  }
}

// The FLOPs of the network training steps: one forward pass of the trained network for one sample, and the
// whole step (every network it runs, forward and backward, at the step's batch).
void printNetworkFlops(const std::vector<std::vector<bench::Measurement>>& groups) {
  bool header = false;
  for (const std::vector<bench::Measurement>& group : groups) {
    for (const bench::Measurement& m : group) {
      if (m.forwardFlops <= 0 || !m.notRun.empty()) continue;
      if (!header) std::printf("\n%-36s %18s %14s\n", "FLOPs of a recorded step", "forward, 1 sample", "whole step");
      header = true;
      std::printf("%-36s %12.4f GFLOP %8.3f GFLOP\n", m.name.c_str(), m.forwardFlops / 1e9, m.flops / 1e9);
    }
  }
}

struct Results {
  std::vector<std::vector<bench::Measurement>> groups;  // one per benchmark, in order
  bench::DeviceReference reference;                     // the best reading of each
};

bench::DeviceReference best(const bench::DeviceReference& a, const bench::DeviceReference& b) {
  return {std::max(a.peakGflops, b.peakGflops), std::max(a.bandwidthGbps, b.bandwidthGbps)};
}

// Runs the selection `args.passes` times, the references before and after each pass; keeps the fastest
// median of every measurement and the best reference reading.
Results runPasses(Context& context, const std::vector<const bench::Benchmark*>& selected, const BenchArguments& args) {
  Results results;
  for (int pass = 0; pass < args.passes; ++pass) {
    if (args.reference) results.reference = best(results.reference, bench::measureDeviceReference(context, args.options));
    bench::BenchContext bench(context, args.options);
    for (std::size_t b = 0; b < selected.size(); ++b) {
      const std::size_t first = bench.results().size();
      selected[b]->run(bench);
      const std::vector<bench::Measurement> group(bench.results().begin() + static_cast<std::ptrdiff_t>(first),
                                                  bench.results().end());
      if (pass == 0) {
        results.groups.push_back(group);
        continue;
      }
      std::vector<bench::Measurement>& kept = results.groups[b];
      for (std::size_t m = 0; m < group.size() && m < kept.size(); ++m)
        if (group[m].notRun.empty() && (!kept[m].notRun.empty() || group[m].medianNs < kept[m].medianNs))
          kept[m] = group[m];
    }
    if (args.reference) results.reference = best(results.reference, bench::measureDeviceReference(context, args.options));
    if (!args.json && args.passes > 1) std::fprintf(stderr, "bench: pass %d of %d done\n", pass + 1, args.passes);
  }
  return results;
}

void printJson(const Context& context, const Results& results) {
  const bench::DeviceReference& reference = results.reference;
  nlohmann::json list = nlohmann::json::array();
  for (const std::vector<bench::Measurement>& group : results.groups)
    for (const bench::Measurement& m : group) {
      nlohmann::json entry{{"kernel", m.name}, {"shape", m.shape}, {"median_ns", m.medianNs},
                           {"median_cpu_ns", m.medianCpuNs}, {"runs", m.runs},
                           {"bytes", m.bytes}, {"flops", m.flops}, {"gb_per_s", m.gbPerSecond()},
                           {"gflop_per_s", m.gflopPerSecond()},
                           {"percent_of_copy", percent(m.gbPerSecond(), reference.bandwidthGbps)},
                           {"percent_of_peak", percent(m.gflopPerSecond(), reference.peakGflops)}};
      if (!m.notRun.empty()) entry["not_run"] = m.notRun;
      if (!m.profile.shaders.empty()) {
        entry["profile"] = nlohmann::json::array();
        for (const bench::ProfileLine& line : m.profile.shaders)
          entry["profile"].push_back({{"shader", line.shader}, {"ns", line.nanoseconds}, {"dispatches", line.dispatches}});
      }
      if (!m.profile.dispatches.empty()) {
        entry["slowest_dispatches"] = nlohmann::json::array();
        for (const bench::DispatchLine& line : m.profile.dispatches)
          entry["slowest_dispatches"].push_back({{"shader", line.shader}, {"ns", line.nanoseconds}, {"detail", line.detail}});
      }
      if (m.forwardFlops > 0) entry["forward_flops"] = m.forwardFlops;
      if (m.heldBytes > 0) {
        entry["held_bytes"] = m.heldBytes;
        entry["held_bytes_without_reuse"] = m.heldBytesWithoutReuse;
        entry["pool_peak_bytes"] = m.poolPeakBytes;
      }
      list.push_back(std::move(entry));
    }
  std::cout << nlohmann::json{{"device", context.info().name}, {"driver", context.info().driver},
                              {"device_type", context.info().typeName()},
                              {"reference", {{"peak_gflop_per_s", reference.peakGflops},
                                             {"copy_gb_per_s", reference.bandwidthGbps}}},
                              {"results", list}}
                   .dump(2)
            << "\n";
}

void addBenchCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static BenchArguments args;
  CLI::App* command = app.add_subcommand("bench", "time kernels on the device (GPU timestamps, median of runs)");
  command->add_option("filter", args.filter, "run only benchmarks whose name contains this text");
  command->add_flag("--json", args.json, "print JSON");
  command->add_flag("--list", args.list, "list benchmark names and exit");
  command->add_option("--runs", args.options.runs, "timed runs per kernel (median is reported)")->check(wholeNumber(1, 100000));
  command->add_option("--warmup", args.options.warmup, "untimed runs before timing")->check(wholeNumber(0, 100000));
  command->add_option("--passes", args.passes, "run everything this many times and keep each figure's best pass")
      ->check(wholeNumber(1, 1000));
  command->add_flag("--profile", args.options.profile,
                    "also time every dispatch of each recording once and print each shader's share");
  command->add_option("--profile-dispatches", args.options.slowestDispatches,
                      "with --profile (which it implies): also list each recording's N slowest dispatches with their "
                      "workgroup grid, specialisation constants and push constants, which tell their shapes")
      ->check(wholeNumber(0, 100000));
  command->add_flag("!--no-reference", args.reference,
                    "skip measuring the reference figures (loop-FMA peak, copy bandwidth) and the % columns");
  command->callback([&global, &action] {
    if (args.options.slowestDispatches > 0) args.options.profile = true;
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
      if (!args.json) std::cout << "device: " << context.info().name << " (" << context.info().driver << ")" << std::endl;
      const Results results = runPasses(context, selected, args);
      if (args.json) {
        printJson(context, results);
        return;
      }
      if (args.reference)
        std::printf("reference (best reading): loop-FMA peak %.2f GFLOP/s, kernel copy %.2f GB/s\n",
                    results.reference.peakGflops, results.reference.bandwidthGbps);
      if (args.passes > 1) std::printf("each figure is the best of %d passes\n", args.passes);
      for (const std::vector<bench::Measurement>& group : results.groups) printTable(group, results.reference);
      printMemory(results.groups);
      printNetworkFlops(results.groups);
      for (const std::vector<bench::Measurement>& group : results.groups) printProfiles(group);
    };
  });
}

const bool registered = registerCommand({"bench", addBenchCommand});

}  // namespace
}  // namespace smokesvd::cli

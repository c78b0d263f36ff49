#include "tools/bench/bench.h"

#include <algorithm>
#include <chrono>
#include <map>

#include <sys/resource.h>

#include "nets/ops/elementwise.h"
#include "runtime/error.h"
#include "runtime/name_registry.h"

namespace smokesvd::bench {
namespace {

NameRegistry<Benchmark>& registry() {
  static NameRegistry<Benchmark> all("benchmark");
  return all;
}

}  // namespace

bool registerBenchmark(Benchmark benchmark) { return registry().add(std::move(benchmark)); }

const std::vector<Benchmark>& benchmarks() { return registry().all(); }

LongRunTiming::LongRunTiming(BenchContext& b) : b_(b), given_(b.options()) {
  b.setOptions({.warmup = std::min(given_.warmup, 1), .runs = std::min(given_.runs, 5), .profile = given_.profile,
                .slowestDispatches = given_.slowestDispatches});
}

void addNotRun(BenchContext& b, const std::string& name, const std::string& why) {
  b.add({.name = name, .shape = "-", .notRun = why});
}

Tensor filled(Context& context, const Shape& shape, float value) {
  Tensor tensor(context, shape);
  Stream stream(context);
  ops::fill(stream, tensor, value);
  stream.submit();
  return tensor;
}

namespace {

// CPU time of the whole process (every thread) so far, in nanoseconds.
double processCpuNs() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  auto ns = [](const timeval& t) { return (static_cast<double>(t.tv_sec) * 1e6 + static_cast<double>(t.tv_usec)) * 1e3; };
  return ns(usage.ru_utime) + ns(usage.ru_stime);
}

constexpr int kProfileRuns = 3;

double median(std::vector<double> samples) {
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(samples.size() / 2), samples.end());
  return samples[samples.size() / 2];
}

}  // namespace

BenchContext::Times BenchContext::time(const std::function<void(Stream&)>& work, StreamOptions streamOptions,
                                       StreamMemory* memory) {
  Stream stream(context_, streamOptions);
  stream.beginRegion("work");
  work(stream);
  stream.endRegion();
  if (memory) *memory = stream.memory();
  const bool gpuTimes = context_.info().timestamps;
  std::vector<double> samples, cpu;
  for (int run = 0; run < options_.warmup + options_.runs; ++run) {
    const double cpuStart = processCpuNs();
    const auto start = std::chrono::steady_clock::now();
    stream.submit();
    const auto stop = std::chrono::steady_clock::now();
    const double cpuStop = processCpuNs();
    if (run < options_.warmup) continue;
    samples.push_back(gpuTimes ? stream.regionTimes().at(0).nanoseconds
                               : std::chrono::duration<double, std::nano>(stop - start).count());
    cpu.push_back(cpuStop - cpuStart);
  }
  return {median(samples), median(cpu)};
}

Profile BenchContext::profile(const std::function<void(Stream&)>& work, StreamOptions streamOptions) {
  streamOptions.profileDispatches = true;
  streamOptions.maxRegions = 1 << 16;
  Stream stream(context_, streamOptions);
  work(stream);
  stream.submit();
  // Each dispatch keeps its fastest of a few runs: on a shared machine one run's dispatches are each
  // delayed by whatever else ran at that moment.
  std::vector<RegionTime> fastest;
  for (int run = 0; run < kProfileRuns; ++run) {
    stream.submit();
    const std::vector<RegionTime> times = stream.regionTimes();
    if (fastest.empty()) fastest = times;
    for (std::size_t i = 0; i < times.size(); ++i) fastest[i].nanoseconds = std::min(fastest[i].nanoseconds, times[i].nanoseconds);
  }
  std::map<std::string, ProfileLine> byShader;
  for (const RegionTime& region : fastest) {
    ProfileLine& line = byShader[region.name];
    line.shader = region.name;
    line.nanoseconds += region.nanoseconds;
    ++line.dispatches;
  }
  Profile result;
  for (auto& [name, line] : byShader) result.shaders.push_back(std::move(line));
  std::sort(result.shaders.begin(), result.shaders.end(),
            [](const ProfileLine& a, const ProfileLine& b) { return a.nanoseconds > b.nanoseconds; });
  std::sort(fastest.begin(), fastest.end(), [](const RegionTime& a, const RegionTime& b) { return a.nanoseconds > b.nanoseconds; });
  const auto kept = std::min<std::size_t>(fastest.size(), static_cast<std::size_t>(std::max(options_.slowestDispatches, 0)));
  for (std::size_t i = 0; i < kept; ++i) result.dispatches.push_back({fastest[i].name, fastest[i].detail, fastest[i].nanoseconds});
  return result;
}

void BenchContext::measure(std::string name, std::string shape, double bytes, double flops,
                           const std::function<void(Stream&)>& work) {
  Measurement measurement;
  measurement.name = std::move(name);
  measurement.shape = std::move(shape);
  measurement.bytes = bytes;
  measurement.flops = flops;
  measurement.runs = options_.runs;
  const Times times = time(work);
  measurement.medianNs = times.gpuNs;
  measurement.medianCpuNs = times.cpuNs;
  if (options_.profile) measurement.profile = profile(work);
  results_.push_back(std::move(measurement));
}

void BenchContext::measureStep(std::string name, std::string shape, double flops, StreamOptions streamOptions,
                               const std::function<void(Stream&)>& work) {
  BufferPool& pool = context_.buffers();
  pool.trim();
  pool.resetPeaks();
  Measurement measurement;
  measurement.name = std::move(name);
  measurement.shape = std::move(shape);
  measurement.flops = flops;
  measurement.runs = options_.runs;
  StreamMemory memory;
  const Times times = time(work, streamOptions, &memory);
  measurement.medianNs = times.gpuNs;
  measurement.medianCpuNs = times.cpuNs;
  measurement.heldBytes = memory.heldBytes;
  measurement.heldBytesWithoutReuse = memory.bytesWithoutReuse();
  measurement.poolPeakBytes = pool.stats().peakAllocatedBytes;
  if (options_.profile) measurement.profile = profile(work, streamOptions);
  results_.push_back(std::move(measurement));
}

}  // namespace smokesvd::bench

#include "tools/bench/bench.h"

#include <algorithm>
#include <chrono>

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

Tensor filled(Context& context, const Shape& shape, float value) {
  Tensor tensor(context, shape);
  Stream stream(context);
  ops::fill(stream, tensor, value);
  stream.submit();
  return tensor;
}

double BenchContext::timeMedian(const std::function<void(Stream&)>& work, StreamOptions streamOptions,
                                StreamMemory* memory) {
  Stream stream(context_, streamOptions);
  stream.beginRegion("work");
  work(stream);
  stream.endRegion();
  if (memory) *memory = stream.memory();
  const bool gpuTimes = context_.info().timestamps;
  std::vector<double> samples;
  for (int run = 0; run < options_.warmup + options_.runs; ++run) {
    const auto start = std::chrono::steady_clock::now();
    stream.submit();
    const auto stop = std::chrono::steady_clock::now();
    if (run < options_.warmup) continue;
    samples.push_back(gpuTimes ? stream.regionTimes().at(0).nanoseconds
                               : std::chrono::duration<double, std::nano>(stop - start).count());
  }
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(samples.size() / 2), samples.end());
  return samples[samples.size() / 2];
}

void BenchContext::measure(std::string name, std::string shape, double bytes, double flops,
                           const std::function<void(Stream&)>& work) {
  Measurement measurement;
  measurement.name = std::move(name);
  measurement.shape = std::move(shape);
  measurement.bytes = bytes;
  measurement.flops = flops;
  measurement.runs = options_.runs;
  measurement.medianNs = timeMedian(work);
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
  measurement.medianNs = timeMedian(work, streamOptions, &memory);
  measurement.heldBytes = memory.heldBytes;
  measurement.heldBytesWithoutReuse = memory.bytesWithoutReuse();
  measurement.poolPeakBytes = pool.stats().peakAllocatedBytes;
  results_.push_back(std::move(measurement));
}

}  // namespace smokesvd::bench

// The benchmark registry behind `smokesvd bench`. A benchmark records its work into a Stream once;
// the driver re-submits that recording (warm-up, then many timed runs) and reports the median GPU time.
//
// Adding one: in any tools/bench/*.cpp,
//   static const bool registered = registerBenchmark({"group/name", [](BenchContext& b) { ... b.report(...); }});
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "runtime/context.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::bench {

struct Measurement {
  std::string name;        // e.g. "copy/texel"
  std::string shape;       // what was run, e.g. "[16777216]" or "3x3 64->64 @ 64x64"
  double medianNs = 0;     // median GPU time of one run
  double bytes = 0;        // bytes read + written by one run (0 if not memory-bound)
  double flops = 0;        // floating-point operations of one run (0 if not compute-bound)
  int runs = 0;
  // Training steps (BenchContext::measureStep): the memory the recording holds (Stream::memory), what it
  // would hold without buffer reuse, and the pool's high-water mark while it was recorded and run.
  uint64_t heldBytes = 0;
  uint64_t heldBytesWithoutReuse = 0;
  uint64_t poolPeakBytes = 0;
  double gbPerSecond() const { return bytes > 0 ? bytes / medianNs : 0; }
  double gflopPerSecond() const { return flops > 0 ? flops / medianNs : 0; }
};

struct BenchOptions {
  int warmup = 3;
  int runs = 15;
};

class BenchContext {
 public:
  BenchContext(Context& context, BenchOptions options) : context_(context), options_(options) {}
  Context& context() { return context_; }
  // Records `work` once into a stream with `streamOptions`, runs it options.warmup + options.runs times,
  // returns the median GPU time (ns); `memory` receives what the recording held, if given.
  double timeMedian(const std::function<void(Stream&)>& work, StreamOptions streamOptions = {},
                    StreamMemory* memory = nullptr);
  // Times `work` and adds a measurement.
  void measure(std::string name, std::string shape, double bytes, double flops,
               const std::function<void(Stream&)>& work);
  // Times a training step and adds a measurement with its memory figures. Idle pool buffers are freed
  // first, so the pool's peak is the device memory this step needs with everything it keeps alive.
  void measureStep(std::string name, std::string shape, double flops, StreamOptions streamOptions,
                   const std::function<void(Stream&)>& work);
  void add(Measurement measurement) { results_.push_back(std::move(measurement)); }
  const std::vector<Measurement>& results() const { return results_; }

 private:
  Context& context_;
  BenchOptions options_;
  std::vector<Measurement> results_;
};

struct Benchmark {
  std::string name;  // "group/name"; the FILTER of `smokesvd bench` matches a substring of it
  std::function<void(BenchContext&)> run;
};

// What the device can do at best, measured at the start of every `smokesvd bench` run so that each
// figure is also read as a fraction of its ceiling on the same device at the same moment (shared or
// throttled machines vary by 2x from one minute to the next).
struct DeviceReference {
  double peakGflops = 0;     // loop-FMA peak (peak/fma-loop)
  double bandwidthGbps = 0;  // the faster of the two kernel copies (copy/texel-read, copy/storage-read)
};
DeviceReference measureDeviceReference(Context& context, BenchOptions options);

// A tensor of `shape` with every element `value` (benchmark inputs).
Tensor filled(Context& context, const Shape& shape, float value);

// Throws Error if a benchmark of that name is already registered (runtime/name_registry.h).
bool registerBenchmark(Benchmark benchmark);
const std::vector<Benchmark>& benchmarks();

}  // namespace smokesvd::bench

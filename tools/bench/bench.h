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

// Where the time of one measurement goes (`--profile`): each shader's total over one run of the
// recording, timed per dispatch.
struct ProfileLine {
  std::string shader;
  double nanoseconds = 0;
  int dispatches = 0;
};

// One dispatch of that run (`--profile-dispatches N` keeps a recording's N slowest): its shader, time, and
// workgroup grid, specialisation constants and push constants (RegionTime::detail), which tell its shape.
struct DispatchLine {
  std::string shader, detail;
  double nanoseconds = 0;
};

struct Profile {
  std::vector<ProfileLine> shaders;     // slowest first
  std::vector<DispatchLine> dispatches;  // the slowest BenchOptions::slowestDispatches, slowest first
};

struct Measurement {
  std::string name;        // e.g. "copy/texel"
  std::string shape;       // what was run, e.g. "[16777216]" or "3x3 64->64 @ 64x64"
  double medianNs = 0;     // median GPU time of one run
  double medianCpuNs = 0;  // median CPU time the process spent during one run (every thread; on a CPU
                           // device the work itself, whatever other processes take of the cores)
  double bytes = 0;        // bytes read + written by one run (0 if not memory-bound)
  double flops = 0;        // floating-point operations of one run (0 if not compute-bound)
  int runs = 0;
  // Training steps (BenchContext::measureStep): the memory the recording holds (Stream::memory), what it
  // would hold without buffer reuse, and the pool's high-water mark while it was recorded and run.
  uint64_t heldBytes = 0;
  uint64_t heldBytesWithoutReuse = 0;
  uint64_t poolPeakBytes = 0;
  // Network training steps (tools/bench/network_training_benchmarks.cpp): one forward pass of the trained
  // network alone for one sample, the model card's figure (0 elsewhere); `flops` is the whole step's.
  double forwardFlops = 0;
  Profile profile;                   // with --profile
  std::string notRun;                // why it was not measured (the device cannot hold it); empty if it was
  double gbPerSecond() const { return bytes > 0 && medianNs > 0 ? bytes / medianNs : 0; }
  double gflopPerSecond() const { return flops > 0 && medianNs > 0 ? flops / medianNs : 0; }
  double gflopPerCpuSecond() const { return flops > 0 && medianCpuNs > 0 ? flops / medianCpuNs : 0; }
};

struct BenchOptions {
  int warmup = 3;
  int runs = 15;
  bool profile = false;  // also run each recording once timed per dispatch (Measurement::profile)
  int slowestDispatches = 0;  // with profile: how many of each recording's slowest dispatches to list
};

class BenchContext {
 public:
  BenchContext(Context& context, BenchOptions options) : context_(context), options_(options) {}
  Context& context() { return context_; }
  struct Times {
    double gpuNs = 0, cpuNs = 0;
  };
  // Records `work` once into a stream with `streamOptions`, runs it options.warmup + options.runs times,
  // returns the median GPU time and the median CPU time of the process per run (ns); `memory` receives
  // what the recording held, if given.
  Times time(const std::function<void(Stream&)>& work, StreamOptions streamOptions = {},
             StreamMemory* memory = nullptr);
  double timeMedian(const std::function<void(Stream&)>& work, StreamOptions streamOptions = {},
                    StreamMemory* memory = nullptr) {
    return time(work, streamOptions, memory).gpuNs;
  }
  // Times `work` and adds a measurement (with its profile when options.profile is set).
  void measure(std::string name, std::string shape, double bytes, double flops,
               const std::function<void(Stream&)>& work);
  // Times a training step and adds a measurement with its memory figures. Idle pool buffers are freed
  // first, so the pool's peak is the device memory this step needs with everything it keeps alive.
  void measureStep(std::string name, std::string shape, double flops, StreamOptions streamOptions,
                   const std::function<void(Stream&)>& work);
  // Records `work` once with a timestamp around every dispatch, runs it a few times after a warm-up and
  // returns the time per shader and the slowest dispatches, each dispatch at its fastest run.
  Profile profile(const std::function<void(Stream&)>& work, StreamOptions streamOptions = {});
  const BenchOptions& options() const { return options_; }
  void setOptions(BenchOptions options) { options_ = options; }
  void add(Measurement measurement) { results_.push_back(std::move(measurement)); }
  Measurement& last() { return results_.back(); }
  const std::vector<Measurement>& results() const { return results_; }

 private:
  Context& context_;
  BenchOptions options_;
  std::vector<Measurement> results_;
};

// Shorter timing for the duration of a benchmark whose run is long (a training step, a network's forward at
// the paper preset): 1 warm-up and at most 5 runs.
class LongRunTiming {
 public:
  explicit LongRunTiming(BenchContext& b);
  ~LongRunTiming() { b_.setOptions(given_); }
  LongRunTiming(const LongRunTiming&) = delete;
  LongRunTiming& operator=(const LongRunTiming&) = delete;

 private:
  BenchContext& b_;
  BenchOptions given_;
};

// Adds a measurement the device could not run (a tensor past its buffer limit, memory exhausted), with why.
void addNotRun(BenchContext& b, const std::string& name, const std::string& why);

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
  // On a CPU device, the loop-FMA kernel's GFLOP per CPU-second of the process (0 on other devices): the
  // ceiling of a core, which the machine's other work does not lower as it lowers the wall-clock figures.
  double peakGflopsPerCpuSecond = 0;
};
DeviceReference measureDeviceReference(Context& context, BenchOptions options);

// A tensor of `shape` with every element `value` (benchmark inputs).
Tensor filled(Context& context, const Shape& shape, float value);

// Throws Error if a benchmark of that name is already registered (runtime/name_registry.h).
bool registerBenchmark(Benchmark benchmark);
const std::vector<Benchmark>& benchmarks();

}  // namespace smokesvd::bench

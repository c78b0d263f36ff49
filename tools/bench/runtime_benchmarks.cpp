// Runtime benchmarks: the arithmetic peak of loop code, memory bandwidth through each read path,
// elementwise kernels, reductions, and the cost of one dispatch inside a batch. Bytes count everything
// read plus everything written.
#include <algorithm>

#include "nets/ops/elementwise.h"
#include "nets/ops/reduce.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

constexpr int64_t kElements = 1 << 24;  // 64 MiB of float32
const std::string kShape = "[16777216]";
constexpr double kBytes = kElements * 4.0;

void kernelCopies(BenchContext& b, const Tensor& x, const Tensor& y) {
  b.measure("copy/texel-read", kShape, 2 * kBytes, 0, [&](Stream& s) { ops::copy(s, x, y); });
  b.measure("copy/storage-read", kShape, 2 * kBytes, 0, [&](Stream& s) {
    struct { uint32_t n; } push{static_cast<uint32_t>(kElements)};
    s.dispatchFlat(s.kernel("tensor/copy_storage", {128, 1, 1}), {x, y}, push, kElements / 4);
  });
}

void copyPaths(BenchContext& b) {
  Tensor x(b.context(), {kElements});
  Tensor y(b.context(), {kElements});
  Stream fill(b.context());
  ops::fill(fill, x, 1.0f);
  fill.submit();
  kernelCopies(b, x, y);
  b.measure("copy/transfer", kShape, 2 * kBytes, 0, [&](Stream& s) { s.copy(x, y); });
}

void elementwise(BenchContext& b) {
  Tensor x(b.context(), {kElements});
  Tensor y(b.context(), {kElements});
  Tensor z(b.context(), {kElements});
  Stream fill(b.context());
  ops::fill(fill, x, 1.0f);
  ops::fill(fill, y, 2.0f);
  fill.submit();
  b.measure("elementwise/fill", kShape, kBytes, 0, [&](Stream& s) { ops::fill(s, z, 3.0f); });
  b.measure("elementwise/add", kShape, 3 * kBytes, kElements, [&](Stream& s) { ops::add(s, x, y, z); });
  b.measure("elementwise/mul", kShape, 3 * kBytes, kElements, [&](Stream& s) { ops::mul(s, x, y, z); });
  b.measure("elementwise/axpy", kShape, 3 * kBytes, 2.0 * kElements, [&](Stream& s) { ops::axpy(s, 0.5f, x, z); });
  b.measure("elementwise/scale", kShape, 2 * kBytes, kElements, [&](Stream& s) { ops::scale(s, x, 0.5f, z); });
}

void reductions(BenchContext& b) {
  const int64_t n = 10'000'000;
  Tensor x(b.context(), {n});
  Tensor out(b.context(), {1});
  Stream fill(b.context());
  ops::fill(fill, x, 1.0f);
  fill.submit();
  b.measure("reduce/sum", "[10000000]", n * 4.0, static_cast<double>(n), [&](Stream& s) {
    ops::reduceAll(s, ops::Reduction::Sum, x, out);
  });
  b.measure("reduce/max", "[10000000]", n * 4.0, static_cast<double>(n), [&](Stream& s) {
    ops::reduceAll(s, ops::Reduction::Max, x, out);
  });
}

// The loop-FMA ceiling (shaders/bench/fma_peak.comp): 64 FLOPs per round, 256 rounds, 2^16 invocations. The
// compute-bound benchmarks (convolution, linear) are read as a fraction of this figure.
void fmaPeak(BenchContext& b) {
  constexpr uint32_t kInvocations = 1 << 16;
  constexpr int kIterations = 256;
  Tensor out(b.context(), {kInvocations});
  struct {
    int32_t iterations;
    float seed;
  } push{kIterations, 1.0f};
  b.measure("peak/fma-loop", "8 vec4 chains x 256 x 65536", 0, 64.0 * kIterations * kInvocations,
            [&](Stream& s) { s.dispatchFlat(s.kernel("bench/fma_peak", {64, 1, 1}), {out}, push, kInvocations); });
}

void emptyDispatch(BenchContext& b) {
  constexpr int kBatch = 1000;
  const double total = b.timeMedian([&](Stream& s) {
    const Kernel& empty = s.kernel("tensor/empty", {64, 1, 1});
    for (int i = 0; i < kBatch; ++i) s.dispatch(empty, std::span<const Arg>{}, nullptr, 0, {1, 1, 1});
  });
  Measurement m;
  m.name = "dispatch/empty-in-batch";
  m.shape = "1 of " + std::to_string(kBatch) + " in one submit";
  m.medianNs = total / kBatch;
  m.runs = 1;
  b.add(m);
}

}  // namespace

DeviceReference measureDeviceReference(Context& context, BenchOptions options) {
  BenchContext b(context, options);
  fmaPeak(b);
  Tensor x(context, {kElements});
  Tensor y(context, {kElements});
  Stream fill(context);
  ops::fill(fill, x, 1.0f);
  fill.submit();
  kernelCopies(b, x, y);
  const std::vector<Measurement>& m = b.results();
  return {m[0].gflopPerSecond(), std::max(m[1].gbPerSecond(), m[2].gbPerSecond())};
}

namespace {

const bool registered = registerBenchmark({"copy", copyPaths}) && registerBenchmark({"elementwise", elementwise}) &&
                        registerBenchmark({"reduce", reductions}) && registerBenchmark({"dispatch", emptyDispatch}) &&
                        registerBenchmark({"peak", fmaPeak});

}  // namespace
}  // namespace smokesvd::bench

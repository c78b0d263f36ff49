// Runtime benchmarks: memory bandwidth through each read path, elementwise kernels, reductions, and the
// cost of one dispatch inside a batch. Bytes count everything read plus everything written.
#include "nets/ops/elementwise.h"
#include "nets/ops/reduce.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

constexpr int64_t kElements = 1 << 24;  // 64 MiB of float32
const std::string kShape = "[16777216]";
constexpr double kBytes = kElements * 4.0;

void copyPaths(BenchContext& b) {
  Tensor x(b.context(), {kElements});
  Tensor y(b.context(), {kElements});
  Stream fill(b.context());
  ops::fill(fill, x, 1.0f);
  fill.submit();
  b.measure("copy/texel-read", kShape, 2 * kBytes, 0, [&](Stream& s) { ops::copy(s, x, y); });
  b.measure("copy/storage-read", kShape, 2 * kBytes, 0, [&](Stream& s) {
    struct { uint32_t n; } push{static_cast<uint32_t>(kElements)};
    s.dispatchFlat(s.kernel("tensor/copy_storage", {128, 1, 1}), {x, y}, push, kElements / 4);
  });
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

const bool registered = registerBenchmark({"copy", copyPaths}) && registerBenchmark({"elementwise", elementwise}) &&
                        registerBenchmark({"reduce", reductions}) && registerBenchmark({"dispatch", emptyDispatch});

}  // namespace
}  // namespace smokesvd::bench

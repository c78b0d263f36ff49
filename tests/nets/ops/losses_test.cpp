#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "nets/functional/losses.h"
#include "nets/ops/losses.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class LossesTest : public GpuTest {};

using Images = std::vector<std::vector<double>>;

double mse(std::span<const double> a, std::span<const double> b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return sum / static_cast<double>(a.size());
}

double l1(std::span<const double> a, std::span<const double> b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(a[i] - b[i]);
  return sum / static_cast<double>(a.size());
}

double rowSum(std::span<const double> a, std::span<const double> b, int64_t width) {
  const std::size_t rows = a.size() / static_cast<std::size_t>(width);
  double sum = 0;
  for (std::size_t r = 0; r < rows; ++r) {
    double difference = 0;
    for (int64_t w = 0; w < width; ++w) difference += a[r * width + w] - b[r * width + w];
    sum += difference * difference;
  }
  return sum / static_cast<double>(rows);
}

// Per-sample PSNR of a against b for `samples` equal parts.
std::vector<double> samplePsnr(std::span<const double> a, std::span<const double> b, int64_t samples, double range) {
  const std::size_t length = a.size() / static_cast<std::size_t>(samples);
  std::vector<double> result;
  for (int64_t n = 0; n < samples; ++n) {
    const double m = mse(a.subspan(n * length, length), b.subspan(n * length, length));
    result.push_back(10.0 * std::log10(range * range / (m + 1e-10)));
  }
  return result;
}

double psnr(std::span<const double> a, std::span<const double> b, int64_t samples, double range) {
  double sum = 0;
  for (double p : samplePsnr(a, b, samples, range)) sum += p;
  return sum / static_cast<double>(samples);
}

double psnrGap(std::span<const double> a, std::span<const double> b, std::span<const double> r, int64_t samples,
               double range) {
  const std::vector<double> pa = samplePsnr(a, r, samples, range), pb = samplePsnr(b, r, samples, range);
  double sum = 0;
  for (int64_t n = 0; n < samples; ++n) sum += (pa[n] - pb[n]) * (pa[n] - pb[n]);
  return sum / static_cast<double>(samples);
}

double meanSquared(std::span<const double> x) {
  double sum = 0;
  for (double v : x) sum += v;
  const double mean = sum / static_cast<double>(x.size());
  return mean * mean;
}

struct LossCase {
  std::string name;
  int inputs;
  std::function<Var(Tape&, const std::vector<Var>&)> apply;
  std::function<double(const Images&)> reference;
};

constexpr double kRange = 2.0;

std::vector<LossCase> cases(const Shape& shape) {
  const int64_t samples = shape[0], width = shape.back();
  return {
      {"mse", 2, [](Tape& t, const std::vector<Var>& v) { return fn::mseLoss(t, v[0], v[1]); },
       [](const Images& x) { return mse(x[0], x[1]); }},
      {"l1", 2, [](Tape& t, const std::vector<Var>& v) { return fn::l1Loss(t, v[0], v[1]); },
       [](const Images& x) { return l1(x[0], x[1]); }},
      {"row sum", 2, [](Tape& t, const std::vector<Var>& v) { return fn::rowSumLoss(t, v[0], v[1]); },
       [width](const Images& x) { return rowSum(x[0], x[1], width); }},
      {"psnr", 2, [](Tape& t, const std::vector<Var>& v) { return fn::psnr(t, v[0], v[1], kRange); },
       [samples](const Images& x) { return psnr(x[0], x[1], samples, kRange); }},
      {"psnr gap", 3, [](Tape& t, const std::vector<Var>& v) { return fn::psnrGapLoss(t, v[0], v[1], v[2], kRange); },
       [samples](const Images& x) { return psnrGap(x[0], x[1], x[2], samples, kRange); }},
      {"mean residual squared", 1, [](Tape& t, const std::vector<Var>& v) { return fn::meanResidualSquared(t, v[0]); },
       [](const Images& x) { return meanSquared(x[0]); }},
  };
}

// Every loss, forward and every input's gradient, against the double reference and central differences.
// Random images differ everywhere, so |a - b| stays away from L1's kink.
TEST_F(LossesTest, ValuesAndGradientsMatchReference) {
  for (const Shape& shape : {Shape{3, 2, 5, 7}, Shape{1, 1, 4, 8}}) {
    for (const LossCase& c : cases(shape)) {
      SCOPED_TRACE(c.name + " on " + toString(shape));
      Images values(c.inputs);
      std::vector<Var> vars;
      for (int k = 0; k < c.inputs; ++k) {
        std::vector<float> host;
        vars.push_back(variable(randomTensor(context(), shape, 10 + k, 0, 1, &host), true));
        values[k] = toDouble(host);
      }
      Stream stream(context());
      Tape tape(stream);
      Var loss = c.apply(tape, vars);
      const float upstream = 0.75f;
      tape.backward({{loss, Tensor::fromHost(context(), {1}, std::vector<float>{upstream})}});
      stream.submit();
      EXPECT_EQ(loss->value.shape(), (Shape{1}));
      const double expected = c.reference(values);
      EXPECT_TRUE(allClose(loss->value, std::vector<double>{expected}, {1e-6, 1e-5}));
      for (int k = 0; k < c.inputs; ++k) {
        const auto f = [&](std::span<const double> p) {
          Images changed = values;
          changed[k].assign(p.begin(), p.end());
          return std::vector<double>{c.reference(changed)};
        };
        const std::vector<double> numeric = numericVjp(f, values[k], std::vector<double>{upstream});
        EXPECT_TRUE(allClose(vars[k]->grad, numeric, {1e-6, 1e-4})) << "gradient of input " << k;
      }
    }
  }
}

TEST_F(LossesTest, ForwardKernelsWriteEveryOutput) {
  const Shape shape{5, 1, 11, 13};
  std::vector<float> a, b;
  Tensor ta = randomTensor(context(), shape, 1, 0, 1, &a);
  Tensor tb = randomTensor(context(), shape, 2, 0, 1, &b);
  Tensor mseOut = poisonedTensor(context(), {1}), l1Out = poisonedTensor(context(), {1});
  Tensor rows = poisonedTensor(context(), {55}), rowOut = poisonedTensor(context(), {1});
  Tensor sampleMse = poisonedTensor(context(), {5}), psnrOut = poisonedTensor(context(), {1});
  Stream stream(context());
  ops::mseLoss(stream, ta, tb, mseOut);
  ops::l1Loss(stream, ta, tb, l1Out);
  ops::rowSumLoss(stream, ta, tb, rows, rowOut);
  ops::sampleMse(stream, ta, tb, sampleMse);
  ops::psnr(stream, sampleMse, {}, psnrOut);
  stream.submit();
  const std::vector<double> da = toDouble(a), db = toDouble(b);
  std::vector<double> expectedRows(55, 0.0), expectedMse(5, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    expectedRows[i / 13] += da[i] - db[i];
    expectedMse[i / 143] += (da[i] - db[i]) * (da[i] - db[i]) / 143.0;
  }
  EXPECT_TRUE(allClose(mseOut, std::vector<double>{mse(da, db)}, {1e-6, 1e-5}));
  EXPECT_TRUE(allClose(l1Out, std::vector<double>{l1(da, db)}, {1e-6, 1e-5}));
  EXPECT_TRUE(allClose(rows, expectedRows, {1e-5, 1e-5}));
  EXPECT_TRUE(allClose(rowOut, std::vector<double>{rowSum(da, db, 13)}, {1e-6, 1e-5}));
  EXPECT_TRUE(allClose(sampleMse, expectedMse, {1e-6, 1e-5}));
  EXPECT_TRUE(allClose(psnrOut, std::vector<double>{psnr(da, db, 5, 1.0)}, {1e-4, 1e-5}));
}

TEST_F(LossesTest, L1SubgradientIsZeroWhereInputsAgree) {
  const std::vector<float> values{0.5f, -1.0f, 2.0f};
  Var a = variable(Tensor::fromHost(context(), {3}, values), true);
  Var b = variable(Tensor::fromHost(context(), {3}, std::vector<float>{0.5f, 0.0f, 2.0f}), true);
  Stream stream(context());
  Tape tape(stream);
  tape.backward(fn::l1Loss(tape, a, b));
  stream.submit();
  EXPECT_TRUE(allClose(a->grad, std::vector<double>{0.0, -1.0 / 3, 0.0}, {1e-7, 0}));
  EXPECT_TRUE(allClose(b->grad, std::vector<double>{0.0, 1.0 / 3, 0.0}, {1e-7, 0}));
}

// Every loss through the runner, forward and backward, against the references above.
TEST(LossesCommand, RunsEveryLoss) {
  const Shape shape{2, 1, 3, 4};
  Images values;
  std::map<std::string, io::NpyArray> files;
  for (const std::string name : {"a", "b", "reference"}) {
    const std::vector<float> host = randomValues(24, values.size() + 1, 0, 1);
    values.push_back(toDouble(host));
    files[name] = io::NpyArray::fromFloats(shape, host);
  }
  files["grad_loss"] = io::NpyArray::fromFloats({1}, {1});
  const std::map<std::string, double> expected{{"mse_loss", mse(values[0], values[1])},
                                               {"l1_loss", l1(values[0], values[1])},
                                               {"row_sum_loss", rowSum(values[0], values[1], 4)},
                                               {"psnr", psnr(values[0], values[1], 2, 1.0)},
                                               {"psnr_gap_loss", psnrGap(values[0], values[1], values[2], 2, 1.0)},
                                               {"mean_residual_squared", meanSquared(values[0])}};
  for (const auto& [op, value] : expected) {
    std::map<std::string, io::NpyArray> inputs{{"grad_loss", files["grad_loss"]}};
    if (op == "mean_residual_squared") {
      inputs["x"] = files["a"];
    } else {
      inputs["a"] = files["a"];
      inputs["b"] = files["b"];
      if (op == "psnr_gap_loss") inputs["reference"] = files["reference"];
    }
    const std::string gradient = op == "mean_residual_squared" ? "grad_x" : "grad_a";
    const OpRun run = runOpCommand(op, inputs, {"loss", gradient});
    ASSERT_EQ(run.exitCode, 0) << op << ": " << run.err;
    EXPECT_TRUE(allClose(run.outputs.at("loss").floats, std::vector<double>{value}, {1}, {1e-5, 1e-5})) << op;
    EXPECT_EQ(run.outputs.at(gradient).shape, shape) << op;
  }
}

}  // namespace
}  // namespace smokesvd::testing

#include <gtest/gtest.h>

#include "nets/ops/elementwise.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class ElementwiseTest : public GpuTest, public ::testing::WithParamInterface<int64_t> {};

TEST_P(ElementwiseTest, Fill) {
  const int64_t n = GetParam();
  Tensor y = poisonedTensor(context(), {n});
  Stream stream(context());
  ops::fill(stream, y, 2.5f);
  stream.submit();
  EXPECT_TRUE(allClose(y, std::vector<double>(static_cast<std::size_t>(n), 2.5)));
}

TEST_P(ElementwiseTest, CopyAddSubMulDiv) {
  const int64_t n = GetParam();
  std::vector<float> a, b;
  Tensor ta = randomTensor(context(), {n}, 1, -2, 2, &a);
  Tensor tb = randomTensor(context(), {n}, 2, 0.5f, 3, &b);
  const std::vector<std::pair<ops::BinaryOp, double (*)(double, double)>> cases = {
      {ops::BinaryOp::Add, [](double x, double y) { return x + y; }},
      {ops::BinaryOp::Sub, [](double x, double y) { return x - y; }},
      {ops::BinaryOp::Mul, [](double x, double y) { return x * y; }},
      {ops::BinaryOp::Div, [](double x, double y) { return x / y; }},
  };
  for (const auto& [op, reference] : cases) {
    Tensor y = poisonedTensor(context(), {n});
    Stream stream(context());
    ops::binary(stream, op, ta, tb, y);
    stream.submit();
    std::vector<double> expected(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) expected[i] = reference(a[i], b[i]);
    EXPECT_TRUE(allClose(y, expected)) << "op " << static_cast<int>(op);
  }
  Tensor copied = poisonedTensor(context(), {n});
  Stream stream(context());
  ops::copy(stream, ta, copied);
  stream.submit();
  EXPECT_TRUE(allClose(copied, a, {0, 0}));
}

TEST_P(ElementwiseTest, AxpyAndScale) {
  const int64_t n = GetParam();
  std::vector<float> x, y;
  Tensor tx = randomTensor(context(), {n}, 3, -1, 1, &x);
  Tensor ty = randomTensor(context(), {n}, 4, -1, 1, &y);
  Tensor scaled = poisonedTensor(context(), {n});
  Stream stream(context());
  ops::scale(stream, tx, -3.0f, scaled);
  ops::axpy(stream, 0.25f, tx, ty);  // in place
  stream.submit();
  std::vector<double> expectedScaled(x.size()), expectedAxpy(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    expectedScaled[i] = -3.0 * x[i];
    expectedAxpy[i] = 0.25 * x[i] + y[i];
  }
  EXPECT_TRUE(allClose(scaled, expectedScaled));
  EXPECT_TRUE(allClose(ty, expectedAxpy));
}

INSTANTIATE_TEST_SUITE_P(OddSizes, ElementwiseTest, ::testing::Values(1, 2, 3, 5, 127, 129, 1001, 100003));

TEST_F(GpuTest, ElementwiseRejectsShapeMismatch) {
  Tensor a(context(), {3, 4});
  Tensor b(context(), {4, 3});
  Stream stream(context());
  EXPECT_THROW(ops::add(stream, a, b, a), Error);
}

}  // namespace
}  // namespace smokesvd::testing

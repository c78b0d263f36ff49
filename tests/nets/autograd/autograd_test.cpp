#include <gtest/gtest.h>

#include "nets/functional/elementwise.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class AutogradTest : public GpuTest {};

// f(a, b) = 3 (a b + a) - b, where a is used twice: gradients must accumulate.
std::vector<double> reference(std::span<const double> a, std::span<const double> b) {
  std::vector<double> y(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) y[i] = 3 * (a[i] * b[i] + a[i]) - b[i];
  return y;
}

TEST_F(AutogradTest, ComposedOpsMatchFiniteDifferences) {
  const Shape shape{3, 7};
  std::vector<float> a, b, g;
  Var va = variable(randomTensor(context(), shape, 1, -1, 1, &a), true, "a");
  Var vb = variable(randomTensor(context(), shape, 2, -1, 1, &b), true, "b");
  Tensor upstream = randomTensor(context(), shape, 3, -1, 1, &g);
  Stream stream(context());
  Tape tape(stream);
  Var y = fn::sub(tape, fn::scale(tape, fn::add(tape, fn::mul(tape, va, vb), va), 3.0f), vb);
  tape.backward({{y, upstream}});
  stream.submit();

  const std::vector<double> da = toDouble(a), db = toDouble(b), dg = toDouble(g);
  EXPECT_TRUE(allClose(y->value, reference(da, db)));
  const auto expectedA = numericVjp([&](std::span<const double> x) { return reference(x, db); }, da, dg);
  const auto expectedB = numericVjp([&](std::span<const double> x) { return reference(da, x); }, db, dg);
  EXPECT_TRUE(allClose(va->grad, expectedA, {1e-4, 1e-4}));
  EXPECT_TRUE(allClose(vb->grad, expectedB, {1e-4, 1e-4}));
}

TEST_F(AutogradTest, LossSeedIsOne) {
  Var x = variable(Tensor::fromHost(context(), {4}, std::vector<float>{1, 2, 3, 4}), true);
  Stream stream(context());
  Tape tape(stream);
  tape.backward(fn::scale(tape, x, 2.5f));
  stream.submit();
  EXPECT_TRUE(allClose(x->grad, std::vector<double>(4, 2.5), {0, 0}));
}

TEST_F(AutogradTest, NoGradRecordsNothing) {
  Var x = variable(randomTensor(context(), {5}, 1), true);
  Stream stream(context());
  Tape tape(stream);
  {
    NoGrad inference(tape);
    Var y = fn::mul(tape, x, x);
    EXPECT_FALSE(y->requiresGrad);
  }
  EXPECT_EQ(tape.recordedOps(), 0u);
  Var z = fn::mul(tape, x, x);
  EXPECT_TRUE(z->requiresGrad);
  EXPECT_EQ(tape.recordedOps(), 1u);
  stream.submit();
}

TEST_F(AutogradTest, ConstantsGetNoGradient) {
  Var x = variable(randomTensor(context(), {5}, 1), true);
  Var c = variable(randomTensor(context(), {5}, 2), false);
  Stream stream(context());
  Tape tape(stream);
  tape.backward(fn::mul(tape, x, c));
  stream.submit();
  EXPECT_TRUE(x->grad.defined());
  EXPECT_FALSE(c->grad.defined());
}

}  // namespace
}  // namespace smokesvd::testing

#include <gtest/gtest.h>

#include <cmath>

#include "nets/functional/losses.h"
#include "nets/modules/activation.h"
#include "nets/modules/linear.h"
#include "nets/modules/res_block.h"
#include "nets/optim/adam.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using namespace modules;

// A fixed batch of a smooth 4 -> 3 function to fit.
struct Batch {
  Var x, y;
};

Batch regressionBatch(Context& context, int64_t samples) {
  const std::vector<float> x = randomValues(static_cast<std::size_t>(samples * 4), 21, -1, 1);
  std::vector<float> y(static_cast<std::size_t>(samples * 3));
  for (int64_t n = 0; n < samples; ++n) {
    const float* in = &x[static_cast<std::size_t>(n * 4)];
    float* out = &y[static_cast<std::size_t>(n * 3)];
    out[0] = std::sin(2 * in[0]) + in[1] * in[2];
    out[1] = std::cos(in[3]) - 0.5f * in[0];
    out[2] = in[1] * in[1] - in[2] * in[3];
  }
  return {variable(Tensor::fromHost(context, {samples, 4}, x)),
          variable(Tensor::fromHost(context, {samples, 3}, y))};
}

std::shared_ptr<Sequential> mlp(Context& context) {
  auto net = std::make_shared<Sequential>();
  net->add(std::make_shared<Linear>(context, 4, 32));
  net->add(std::make_shared<Activation>(ActivationKind::SiLU));
  net->add(std::make_shared<Linear>(context, 32, 32));
  net->add(std::make_shared<Activation>(ActivationKind::SiLU));
  net->add(std::make_shared<Linear>(context, 32, 3));
  net->initialize(5);
  return net;
}

class TrainingTest : public GpuTest {};

// One training step (forward, loss, backward, AdamW with a warm-up and cosine schedule) is recorded once and submitted again and again:
// the loss on the batch must fall a hundredfold.
TEST_F(TrainingTest, MlpFitsAFixedBatchFromOneRecording) {
  const Batch batch = regressionBatch(context(), 32);
  auto net = mlp(context());
  const NamedParameters parameters = net->namedParameters();
  optim::Adam adam(context(), parameters,
                   optim::AdamOptions::adamW(optim::LrSchedule::cosine(3e-2, 150, 3e-3, 10), 1e-4));

  Stream stream(context());
  Tape tape(stream);
  const Var loss = fn::mseLoss(tape, net->forward(tape, batch.x), batch.y);
  tape.backward(loss);
  adam.step(stream);

  float first = 0;
  for (int step = 0; step < 150; ++step) {
    stream.submit();
    if (step == 0) first = loss->value.download()[0];
  }
  const float last = loss->value.download()[0];
  EXPECT_GT(first, 0.1f);
  EXPECT_LT(last, first / 100) << "loss went from " << first << " to " << last;
  EXPECT_EQ(adam.steps(), 150);
}

// Recording each step anew (clearing gradients in between) gives the same parameters as submitting
// one recording: nothing carries over between submissions that should not.
TEST_F(TrainingTest, ResubmittingEqualsRecordingEachStep) {
  const Batch batch = regressionBatch(context(), 8);
  auto resubmitted = mlp(context()), rerecorded = mlp(context());
  optim::Adam adamA(context(), resubmitted->namedParameters(), optim::AdamOptions{});
  optim::Adam adamB(context(), rerecorded->namedParameters(), optim::AdamOptions{});

  Stream once(context());
  Tape tapeA(once);
  tapeA.backward(fn::mseLoss(tapeA, resubmitted->forward(tapeA, batch.x), batch.y));
  adamA.step(once);
  for (int step = 0; step < 5; ++step) {
    once.submit();
    Stream each(context());
    Tape tapeB(each);
    clearGradients(rerecorded->namedParameters());
    tapeB.backward(fn::mseLoss(tapeB, rerecorded->forward(tapeB, batch.x), batch.y));
    adamB.step(each);
    each.submit();
  }
  const auto a = resubmitted->namedParameters(), b = rerecorded->namedParameters();
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_EQ(a[i].second->value.download(), b[i].second->value.download()) << a[i].first;
}

// Conv -> ResBlock (GroupNorm, SiLU, convolutions, identity shortcut) -> SiLU -> Conv.
std::shared_ptr<Sequential> convNet(Context& context, uint64_t seed) {
  auto net = std::make_shared<Sequential>();
  net->add(std::make_shared<Conv>(context, 2, 2, 8, 3, ConvOptions{1, 1}));
  net->add(std::make_shared<ResBlock>(context, ResBlockOptions{.inChannels = 8, .groups = 2}));
  net->add(std::make_shared<Activation>(ActivationKind::SiLU));
  net->add(std::make_shared<Conv>(context, 2, 8, 1, 3, ConvOptions{1, 1}));
  net->initialize(seed);
  return net;
}

// A conv net learns what a differently initialised copy of itself computes on a fixed batch of images.
TEST_F(TrainingTest, ConvNetFitsATeacherOnAFixedBatch) {
  const Var x = variable(randomTensor(context(), {4, 2, 8, 8}, 3));
  Var target;
  {
    Stream stream(context());
    Tape tape(stream);
    NoGrad inference(tape);
    target = convNet(context(), 100)->forward(tape, x);
    stream.submit();
  }
  auto net = convNet(context(), 5);
  optim::Adam adam(context(), net->namedParameters(),
                   optim::AdamOptions::adamW(optim::LrSchedule::cosine(3e-2, 100, 3e-3, 10), 1e-4));
  Stream stream(context());
  Tape tape(stream);
  const Var loss = fn::mseLoss(tape, net->forward(tape, x), target);
  tape.backward(loss);
  adam.step(stream);
  float first = 0;
  for (int step = 0; step < 100; ++step) {
    stream.submit();
    if (step == 0) first = loss->value.download()[0];
  }
  const float last = loss->value.download()[0];
  EXPECT_GT(first, 0.1f);
  EXPECT_LT(last, first / 100) << "loss went from " << first << " to " << last;
}

}  // namespace
}  // namespace smokesvd::testing

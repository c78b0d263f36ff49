#include <gtest/gtest.h>

#include "nets/functional/losses.h"
#include "nets/models/bottleneck.h"
#include "nets/models/ddpm_unet.h"
#include "nets/models/unet3plus.h"
#include "nets/modules/flop_counter.h"
#include "nets/optim/adam.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using namespace models;

class ModelsTest : public GpuTest {};

int64_t conv(int64_t in, int64_t out, int64_t kernelElements) { return out * in * kernelElements + out; }

TEST_F(ModelsTest, BottleneckHasItsFourConvolutionsAndHalvesWhenDownsampling) {
  Bottleneck block(context(), {3, 8, 16, true, 4, 0.2f});
  // mid = max(16 / 4, 4) = 4: reduce 1^3, conv 3^3, expand 1^3, skip 2^3 stride 2.
  EXPECT_EQ(block.parameterCount(), conv(8, 4, 1) + conv(4, 4, 27) + conv(4, 16, 1) + conv(8, 16, 8));
  const NamedParameters names = block.namedParameters();
  ASSERT_EQ(names.size(), 8u);
  EXPECT_EQ(names[0].first, "reduce.weight");
  EXPECT_EQ(names[6].first, "skip.weight");
  Stream stream(context());
  Tape tape(stream);
  block.initialize(1);
  const Var y = block.forward(tape, variable(randomTensor(context(), {1, 8, 4, 6, 2}, 2)));
  EXPECT_EQ(y->value.shape(), (Shape{1, 16, 2, 3, 1}));
}

TEST_F(ModelsTest, UNet3PlusCountsAndShapes) {
  UNet3PlusConfig config;
  config.dims = 3;
  config.inChannels = 2;
  config.outChannels = 3;
  config.filters = {4, 8};
  config.catChannels = 4;
  config.minMid = 2;
  UNet3Plus net(context(), config);
  // stem 2->4 3^3; down.0 Bottleneck(4->8, down, mid 2); decoder.0: sources Bottleneck(4->4), Bottleneck(8->4),
  // fuse Bottleneck(8->8); heads 8->3 and 8->3.
  const int64_t down = conv(4, 2, 1) + conv(2, 2, 27) + conv(2, 8, 1) + conv(4, 8, 8);
  const int64_t source0 = conv(4, 2, 1) + conv(2, 2, 27) + conv(2, 4, 1) + conv(4, 4, 1);
  const int64_t source1 = conv(8, 2, 1) + conv(2, 2, 27) + conv(2, 4, 1) + conv(8, 4, 1);
  const int64_t fuse = conv(8, 2, 1) + conv(2, 2, 27) + conv(2, 8, 1) + conv(8, 8, 1);
  EXPECT_EQ(net.parameterCount(), conv(2, 4, 27) + down + source0 + source1 + fuse + 2 * conv(8, 3, 1));
  EXPECT_EQ(net.parameterCount(), 1234);

  net.initialize(3);
  Stream stream(context());
  Tape tape(stream);
  const UNet3PlusOutput out = net.forward(tape, variable(randomTensor(context(), {1, 2, 4, 6, 8}, 4)), nullptr, true);
  EXPECT_EQ(out.output->value.shape(), (Shape{1, 3, 4, 6, 8}));
  ASSERT_EQ(out.supervision.size(), 1u);
  EXPECT_EQ(out.supervision[0]->value.shape(), (Shape{1, 3, 4, 6, 8}));
  EXPECT_THROW(net.forward(tape, variable(randomTensor(context(), {1, 2, 4, 5, 8}, 4))), Error);
  EXPECT_THROW(net.forward(tape, variable(randomTensor(context(), {1, 3, 4, 6, 8}, 4))), Error);
}

// A fused map too large for one tensor is kept in channel parts (unet3plus.h): the same outputs and
// parameter gradients as the one-tensor path, 2D and 3D, with every decoder stage in parts.
TEST_F(ModelsTest, UNet3PlusInChannelPartsMatchesTheOneTensorPath) {
  for (const int dims : {2, 3}) {
    UNet3PlusConfig config;
    config.dims = dims;
    config.inChannels = 2;
    config.outChannels = 2;
    config.filters = {4, 6, 8};
    config.catChannels = 3;
    config.minMid = 2;
    UNet3Plus whole(context(), config), inParts(context(), config);
    inParts.setLargestTensorBytes(0);
    const NamedParameters a = whole.namedParameters(), b = inParts.namedParameters();
    for (std::size_t i = 0; i < a.size(); ++i) {  // random, not initial: a fresh block's branch is zero
      const std::vector<float> values = randomValues(a[i].second->value.numel(), 100 + i, -0.5f, 0.5f);
      a[i].second->value.upload(values);
      b[i].second->value.upload(values);
    }
    const Shape inShape = dims == 3 ? Shape{1, 2, 4, 8, 12} : Shape{2, 2, 8, 12};
    Shape outShape = inShape;
    outShape[1] = 2;
    const Tensor x = randomTensor(context(), inShape, 5);
    const Tensor upstream = randomTensor(context(), outShape, 6), upstreamDeep = randomTensor(context(), outShape, 7);

    Stream stream(context());
    Tape tape(stream);
    const UNet3PlusOutput y = whole.forward(tape, variable(x), nullptr, true);
    const UNet3PlusOutput z = inParts.forward(tape, variable(x), nullptr, true);
    tape.backward({{y.output, upstream}, {y.supervision[0], upstreamDeep}, {y.supervision[1], upstream},
                   {z.output, upstream}, {z.supervision[0], upstreamDeep}, {z.supervision[1], upstream}});
    stream.submit();

    const Tolerance tolerance{1e-5, 1e-4};
    EXPECT_TRUE(allClose(z.output->value, y.output->value.download(), tolerance)) << dims << "D";
    for (std::size_t k = 0; k < y.supervision.size(); ++k)
      EXPECT_TRUE(allClose(z.supervision[k]->value, y.supervision[k]->value.download(), tolerance)) << dims << "D head " << k + 1;
    for (std::size_t i = 0; i < a.size(); ++i)
      EXPECT_TRUE(allClose(b[i].second->grad, a[i].second->grad.download(), tolerance)) << dims << "D " << a[i].first;
  }
}

TEST_F(ModelsTest, UNet3PlusPresenceSlotsChangeTheOutputForAnEmptyInput) {
  UNet3PlusConfig config;
  config.inChannels = 4;
  config.filters = {4, 8, 8};
  config.catChannels = 4;
  config.presenceSlots = 4;
  config.output = OutputActivation::ReLU;
  UNet3Plus net(context(), config);
  net.initialize(8);
  const Var zeros = variable(Tensor::fromHost(context(), {1, 4, 4, 8, 4}, std::vector<float>(512, 0.0f)));
  Stream stream(context());
  Tape tape(stream);
  const Var some = net.forward(tape, zeros, variable(Tensor::fromHost(context(), {1, 4}, std::vector<float>{1, 0, 0, 0}))).output;
  const Var all = net.forward(tape, zeros, variable(Tensor::fromHost(context(), {1, 4}, std::vector<float>{1, 1, 1, 1}))).output;
  stream.submit();
  EXPECT_NE(some->value.download(), all->value.download());
  for (const float v : all->value.download()) ASSERT_GE(v, 0.0f);
  EXPECT_THROW(net.forward(tape, zeros), Error);
}

int64_t resBlock(int64_t in, int64_t out, int64_t temb) {
  return 2 * in + conv(in, out, 9) + temb * out + out + 2 * out + conv(out, out, 9) + (in != out ? conv(in, out, 1) : 0);
}

TEST_F(ModelsTest, DdpmUNetCountsShapesAndStartsAtZero) {
  DdpmUNetConfig config;
  config.inChannels = 3;
  config.outChannels = 2;
  config.channels = 8;
  config.channelMult = {1, 2};
  config.resBlocks = 1;
  config.groups = 4;
  DdpmUNet net(context(), config);
  // temb 8->32->32; conv_in 3->8; down.0: block 8->8, downsample 8->8; down.1: block 8->16;
  // mid 16->16 twice; up.1: blocks (16+16)->16, (16+8)->16, upsample 16; up.0: (16+8)->8, (8+8)->8; out 8->2.
  const int64_t expected = (8 * 32 + 32) + (32 * 32 + 32) + conv(3, 8, 9) + resBlock(8, 8, 32) + conv(8, 8, 9) +
                           resBlock(8, 16, 32) + 2 * resBlock(16, 16, 32) + resBlock(32, 16, 32) +
                           resBlock(24, 16, 32) + conv(16, 16, 9) + resBlock(24, 8, 32) + resBlock(16, 8, 32) +
                           2 * 8 + conv(8, 2, 9);
  EXPECT_EQ(net.parameterCount(), expected);
  const NamedParameters names = net.namedParameters();
  EXPECT_EQ(names.front().first, "temb.dense.0.weight");
  EXPECT_EQ(names[4].first, "conv_in.weight");
  EXPECT_EQ(names.back().first, "conv_out.bias");
  bool hasUpsample = false;
  for (const auto& [name, p] : names) hasUpsample |= name == "up.1.upsample.conv.weight";
  EXPECT_TRUE(hasUpsample);

  net.initialize(2);
  Stream stream(context());
  Tape tape(stream);
  const Var eps = net.forward(tape, variable(randomTensor(context(), {2, 3, 6, 10}, 1)),
                              variable(Tensor::fromHost(context(), {2}, std::vector<float>{3, 700})));
  stream.submit();
  EXPECT_EQ(eps->value.shape(), (Shape{2, 2, 6, 10}));
  for (const float v : eps->value.download()) ASSERT_EQ(v, 0.0f);  // conv_out is zero-initialised
}

TEST_F(ModelsTest, FlopCounterCountsConvolutionsAndLinearLayers) {
  modules::Conv c(context(), 3, 4, 6, 3, {1, 1});
  modules::Linear l(context(), 5, 7);
  Stream stream(context());
  Tape tape(stream);
  modules::FlopCounter outer;
  {
    modules::FlopCounter inner;
    c.forward(tape, variable(randomTensor(context(), {1, 4, 3, 5, 7}, 1)));
    EXPECT_DOUBLE_EQ(inner.flops(), 2.0 * (6 * 3 * 5 * 7) * (4 * 27));
  }
  l.forward(tape, variable(randomTensor(context(), {2, 5}, 1)));
  EXPECT_DOUBLE_EQ(outer.flops(), 2.0 * (6 * 3 * 5 * 7) * (4 * 27) + 2.0 * 14 * 5);
}

// A layer's backward FLOPs: its forward's once per input and once per weight that needs a gradient; a
// layer with a trained weight counts its forward and backward as the trained network's.
TEST_F(ModelsTest, FlopCounterCountsTheBackwardPassesALayerRecords) {
  modules::Conv c(context(), 3, 4, 6, 3, {1, 1});
  const double forward = 2.0 * (6 * 3 * 5 * 7) * (4 * 27);
  Stream stream(context());
  Tape tape(stream);
  const Var input = variable(randomTensor(context(), {1, 4, 3, 5, 7}, 1));
  const Var inputNeedingGrad = variable(randomTensor(context(), {1, 4, 3, 5, 7}, 2), true);
  {
    modules::FlopCounter counter;
    c.forward(tape, input);  // weight only
    EXPECT_DOUBLE_EQ(counter.backwardFlops(), forward);
    c.forward(tape, inputNeedingGrad);  // input and weight
    EXPECT_DOUBLE_EQ(counter.backwardFlops(), 3 * forward);
    EXPECT_DOUBLE_EQ(counter.flops(), 2 * forward);
    EXPECT_DOUBLE_EQ(counter.trainedFlops(), 5 * forward);
  }
  for (const auto& [name, parameter] : c.namedParameters()) parameter->requiresGrad = false;
  {
    modules::FlopCounter counter;
    c.forward(tape, input);  // frozen on an input that needs no gradient: no backward
    c.forward(tape, inputNeedingGrad);  // frozen, the gradient passes through to the input
    EXPECT_DOUBLE_EQ(counter.backwardFlops(), forward);
    NoGrad noGrad(tape);
    c.forward(tape, inputNeedingGrad);
    EXPECT_DOUBLE_EQ(counter.backwardFlops(), forward);
    EXPECT_DOUBLE_EQ(counter.flops(), 3 * forward);
    EXPECT_DOUBLE_EQ(counter.trainedFlops(), 0.0);  // frozen
  }
}

// Each architecture fits one fixed sample: the loss falls a hundredfold within a few hundred steps.
float fitOneSample(Context& context, modules::Module& net, const std::function<Var(Tape&)>& loss, int steps) {
  const NamedParameters parameters = net.namedParameters();
  optim::Adam adam(context, parameters, optim::AdamOptions{optim::LrSchedule::constant(3e-3)});
  Stream stream(context);
  Tape tape(stream);
  const Var l = loss(tape);
  tape.backward(l);
  adam.step(stream);
  stream.submit();
  const float first = l->value.download()[0];
  for (int step = 1; step < steps; ++step) stream.submit();
  const float last = l->value.download()[0];
  EXPECT_LT(last, first / 100) << "loss went from " << first << " to " << last;
  return last;
}

TEST_F(ModelsTest, UNet3PlusOverfitsOneSample3D) {
  UNet3PlusConfig config;
  config.inChannels = 2;
  config.outChannels = 1;
  config.filters = {4, 8, 8};
  config.catChannels = 4;
  UNet3Plus net(context(), config);
  net.initialize(1);
  const Var x = variable(randomTensor(context(), {1, 2, 4, 8, 4}, 2, 0, 1));
  const Var y = variable(randomTensor(context(), {1, 1, 4, 8, 4}, 3, 0, 1));
  fitOneSample(context(), net, [&](Tape& tape) { return fn::mseLoss(tape, net.forward(tape, x).output, y); }, 300);
}

TEST_F(ModelsTest, UNet3PlusOverfitsOneSample2D) {
  UNet3PlusConfig config;
  config.dims = 2;
  config.inChannels = 5;
  config.filters = {8, 8, 16};
  config.catChannels = 4;
  UNet3Plus net(context(), config);
  net.initialize(1);
  const Var x = variable(randomTensor(context(), {1, 5, 12, 8}, 2, 0, 1));
  const Var y = variable(randomTensor(context(), {1, 1, 12, 8}, 3, 0, 1));
  fitOneSample(context(), net, [&](Tape& tape) { return fn::mseLoss(tape, net.forward(tape, x).output, y); }, 300);
}

TEST_F(ModelsTest, DdpmUNetOverfitsOneSample) {
  DdpmUNetConfig config;
  config.inChannels = 3;
  config.channels = 8;
  config.channelMult = {1, 2};
  config.resBlocks = 1;
  config.groups = 4;
  DdpmUNet net(context(), config);
  net.initialize(1);
  const Var x = variable(randomTensor(context(), {1, 3, 8, 6}, 2));
  const Var t = variable(Tensor::fromHost(context(), {1}, std::vector<float>{123}));
  const Var eps = variable(randomTensor(context(), {1, 1, 8, 6}, 3));
  fitOneSample(context(), net, [&](Tape& tape) { return fn::mseLoss(tape, net.forward(tape, x, t), eps); }, 300);
}

}  // namespace
}  // namespace smokesvd::testing

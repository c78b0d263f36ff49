#include <gtest/gtest.h>


#include <algorithm>
#include <cmath>
#include <filesystem>

#include "nets/functional/activation.h"
#include "nets/functional/conv.h"
#include "nets/functional/dropout.h"
#include "nets/functional/elementwise.h"
#include "nets/functional/group_norm.h"
#include "nets/io/safetensors.h"
#include "nets/io/temporary_folder.h"
#include "nets/modules/activation.h"
#include "nets/modules/group_norm.h"
#include "nets/modules/linear.h"
#include "nets/modules/res_block.h"
#include "nets/modules/weights.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;
using namespace modules;

std::vector<std::string> namesOf(const Module& module) {
  std::vector<std::string> names;
  for (const auto& [name, parameter] : module.namedParameters()) names.push_back(name);
  return names;
}

// A module with its own parameter and a named child, like a user-written torch.nn.Module.
class Head : public UnaryModule {
 public:
  Head(Context& context, int64_t features) {
    scale_ = addParameter(context, "scale", {features}, Init::constant(1.0));
    body_ = addChild("body", std::make_shared<Sequential>());
    body_->add(std::make_shared<Linear>(context, features, features));
    body_->add(std::make_shared<Activation>(ActivationKind::SiLU));
    body_->add(std::make_shared<Linear>(context, features, 2, false));
  }
  Var forward(Tape& tape, const Var& x) override { return body_->forward(tape, x); }

 private:
  Var scale_;
  std::shared_ptr<Sequential> body_;
};

class ModulesTest : public GpuTest {
 protected:
  io::TemporaryFolder directory_{"modules"};
};

// The names torch gives: Head(nn.Module) with self.scale = nn.Parameter, self.body = nn.Sequential(
// nn.Linear(3, 3), nn.SiLU(), nn.Linear(3, 2, bias=False)): own parameters first, then children in order.
TEST_F(ModulesTest, NamesFollowStateDictConvention) {
  Head head(context(), 3);
  EXPECT_EQ(namesOf(head), (std::vector<std::string>{"scale", "body.0.weight", "body.0.bias", "body.2.weight"}));
  EXPECT_EQ(head.parameterCount(), 3 + 9 + 3 + 6);
  for (const auto& [name, parameter] : head.namedParameters()) EXPECT_TRUE(parameter->requiresGrad) << name;

  ModuleList list;
  list.add(std::make_shared<Head>(context(), 2));
  list.add(std::make_shared<GroupNorm>(context(), 2, 4));
  const std::vector<std::string> names = namesOf(list);
  EXPECT_EQ(names.front(), "0.scale");
  EXPECT_EQ(names.back(), "1.bias");
  EXPECT_EQ(list.size(), 2u);
}

TEST_F(ModulesTest, RejectsBadNames) {
  class Bad : public Module {
   public:
    explicit Bad(Context& context) {
      addParameter(context, "w", {1}, Init::constant(0));
      EXPECT_THROW(addParameter(context, "w", {1}, Init::constant(0)), Error);
      EXPECT_THROW(addParameter(context, "a.b", {1}, Init::constant(0)), Error);
      EXPECT_THROW(addChild("w", std::make_shared<Sequential>()), Error);
    }
  };
  Bad bad(context());
  EXPECT_THROW(GroupNorm(context(), 3, 4), Error);
}

TEST_F(ModulesTest, InitialisationIsSeededByNameAndFollowsTheRules) {
  Head a(context(), 40), b(context(), 40), c(context(), 40);
  a.initialize(7);
  b.initialize(7);
  c.initialize(8);
  const auto pa = a.namedParameters(), pb = b.namedParameters(), pc = c.namedParameters();
  for (std::size_t i = 0; i < pa.size(); ++i) {
    EXPECT_EQ(pa[i].second->value.download(), pb[i].second->value.download()) << pa[i].first;
    if (pa[i].first.ends_with("weight")) {
      EXPECT_NE(pa[i].second->value.download(), pc[i].second->value.download()) << pa[i].first;
    }
  }
  // The same dotted name under the same seed draws the same values in any tree.
  class OnlyBody : public Module {
   public:
    explicit OnlyBody(Context& context) {
      addChild("body", std::make_shared<Sequential>())->add(std::make_shared<Linear>(context, 40, 40));
    }
  };
  OnlyBody other(context());
  other.initialize(7);
  EXPECT_EQ(other.namedParameters()[0].first, "body.0.weight");
  EXPECT_EQ(other.namedParameters()[0].second->value.download(), pa[1].second->value.download());
  Linear alone(context(), 40, 40);
  alone.initialize(7);
  EXPECT_NE(alone.weight()->value.download(), pa[1].second->value.download());  // named "weight"

  // He uniform: U(-b, b), b = sqrt(6 / fan_in), mean 0, variance b^2 / 3; biases 0; scale 1.
  const std::vector<float> w = pa[1].second->value.download();
  const double bound = std::sqrt(6.0 / 40);
  double mean = 0, squares = 0;
  for (float v : w) {
    EXPECT_LT(std::abs(v), bound);
    mean += v;
    squares += static_cast<double>(v) * v;
  }
  mean /= static_cast<double>(w.size());
  EXPECT_NEAR(mean, 0.0, 0.05 * bound);
  EXPECT_NEAR(squares / static_cast<double>(w.size()), bound * bound / 3, 0.1 * bound * bound / 3);
  EXPECT_TRUE(allClose(pa[2].second->value, std::vector<double>(40, 0.0), {0, 0}));
  EXPECT_TRUE(allClose(pa[0].second->value, std::vector<double>(40, 1.0), {0, 0}));

  // PyTorch's default: weights and biases U(-1/sqrt(fan_in), 1/sqrt(fan_in)).
  Linear torchLike(context(), 25, 3, true, WeightInit::TorchDefault);
  torchLike.initialize(1);
  for (const Var& p : {torchLike.weight(), torchLike.bias()}) {
    const std::vector<float> values = p->value.download();
    const float largest = std::abs(*std::max_element(values.begin(), values.end(),
                                                     [](float x, float y) { return std::abs(x) < std::abs(y); }));
    EXPECT_LT(largest, 0.2f);
    EXPECT_GT(largest, 0.05f);
  }
}

TEST_F(ModulesTest, LinearSequentialForwardMatchesReference) {
  Sequential net;
  auto first = net.add(std::make_shared<Linear>(context(), 3, 5));
  net.add(std::make_shared<Activation>(ActivationKind::ReLU));
  net.initialize(3);
  first->bias()->value.upload(randomValues(5, 4));
  std::vector<float> x;
  Var input = variable(randomTensor(context(), {2, 3}, 5, -1, 1, &x));
  Stream stream(context());
  Tape tape(stream);
  Var y = net.forward(tape, input);
  stream.submit();
  const std::vector<float> w = first->weight()->value.download(), b = first->bias()->value.download();
  std::vector<double> expected(10);
  for (int n = 0; n < 2; ++n)
    for (int o = 0; o < 5; ++o) {
      double sum = b[o];
      for (int i = 0; i < 3; ++i) sum += static_cast<double>(x[n * 3 + i]) * w[o * 3 + i];
      expected[n * 5 + o] = std::max(sum, 0.0);
    }
  EXPECT_TRUE(allClose(y->value, expected));
}

TEST_F(ModulesTest, DropoutOnlyInTraining) {
  Sequential net;
  net.add(std::make_shared<Dropout>(0.5f, 1));
  Var x = variable(randomTensor(context(), {64}, 1), true);
  Stream stream(context());
  Tape tape(stream);
  EXPECT_NE(net.forward(tape, x), x);
  net.setTraining(false);
  EXPECT_FALSE(net.children()[0].second->training());
  EXPECT_EQ(net.forward(tape, x), x);
}

TEST_F(ModulesTest, WeightsRoundTripAndMismatchesAreListed) {
  Head saved(context(), 3);
  saved.initialize(11);
  saveWeights(directory_ / "head.safetensors", saved, {{"model", "head"}});
  Head loaded(context(), 3);
  loaded.initialize(12);
  EXPECT_EQ(loadWeights(directory_ / "head.safetensors", loaded).at("model"), "head");
  const auto ps = saved.namedParameters(), pl = loaded.namedParameters();
  for (std::size_t i = 0; i < ps.size(); ++i)
    EXPECT_EQ(ps[i].second->value.download(), pl[i].second->value.download()) << ps[i].first;

  // The file holds names and layouts as PyTorch writes them: linear weight [out, in].
  const io::SafetensorsFile file = io::readSafetensors(directory_ / "head.safetensors");
  EXPECT_EQ(file.find("body.2.weight")->shape, (Shape{2, 3}));

  Head wider(context(), 4);
  try {
    loadWeights(directory_ / "head.safetensors", wider);
    FAIL() << "a model of another shape accepted the weights";
  } catch (const Error& e) {
    const std::string message = e.what();
    for (const char* expected : {"head.safetensors does not match", "4 with a different shape",
                                 "scale (expected [4], file has [3])",
                                 "body.2.weight (expected [2, 4], file has [2, 3])"})
      EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
  Sequential other;
  other.add(std::make_shared<Linear>(context(), 3, 3));
  try {
    loadWeights(directory_ / "head.safetensors", other);
    FAIL();
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("2 missing: 0.weight, 0.bias"), std::string::npos) << message;
    EXPECT_NE(message.find("4 unexpected: scale, body.0.weight, body.0.bias, body.2.weight"), std::string::npos)
        << message;
  }
}

// A DDPM-style tree: temb.dense (ModuleList of Linear), conv_in, down[i].block[j] (ResBlocks, the second
// with a 1x1 shortcut, the last without timestep embedding). Expected names and shapes as printed by
// PyTorch's state_dict() for the same torch.nn tree.
class Down : public Module {
 public:
  explicit Down(std::vector<std::shared_ptr<ResBlock>> blocks) {
    auto list = addChild("block", std::make_shared<ModuleList>());
    for (auto& block : blocks) list->add(block);
  }
};

TEST_F(ModulesTest, ResBlockTreeNamesMatchPyTorch) {
  class Embedding : public Module {
   public:
    explicit Embedding(Context& context) {
      auto dense = addChild("dense", std::make_shared<ModuleList>());
      dense->add(std::make_shared<Linear>(context, 4, 8));
      dense->add(std::make_shared<Linear>(context, 8, 8));
    }
  };
  class Net : public Module {
   public:
    explicit Net(Context& context) {
      addChild("temb", std::make_shared<Embedding>(context));
      addChild("conv_in", std::make_shared<Conv>(context, 2, 3, 4, 3, ConvOptions{1, 1}));
      auto down = addChild("down", std::make_shared<ModuleList>());
      const auto block = [&](int64_t in, int64_t out, int64_t temb) {
        return std::make_shared<ResBlock>(
            context, ResBlockOptions{.inChannels = in, .outChannels = out, .tembChannels = temb, .groups = 2});
      };
      down->add(std::make_shared<Down>(std::vector{block(4, 4, 8), block(4, 6, 8)}));
      down->add(std::make_shared<Down>(std::vector{block(6, 6, 0)}));
    }
  };
  const std::vector<std::pair<std::string, Shape>> expected = {
      {"temb.dense.0.weight", {8, 4}}, {"temb.dense.0.bias", {8}}, {"temb.dense.1.weight", {8, 8}},
      {"temb.dense.1.bias", {8}}, {"conv_in.weight", {4, 3, 3, 3}}, {"conv_in.bias", {4}},
      {"down.0.block.0.norm1.weight", {4}}, {"down.0.block.0.norm1.bias", {4}},
      {"down.0.block.0.conv1.weight", {4, 4, 3, 3}}, {"down.0.block.0.conv1.bias", {4}},
      {"down.0.block.0.temb_proj.weight", {4, 8}}, {"down.0.block.0.temb_proj.bias", {4}},
      {"down.0.block.0.norm2.weight", {4}}, {"down.0.block.0.norm2.bias", {4}},
      {"down.0.block.0.conv2.weight", {4, 4, 3, 3}}, {"down.0.block.0.conv2.bias", {4}},
      {"down.0.block.1.norm1.weight", {4}}, {"down.0.block.1.norm1.bias", {4}},
      {"down.0.block.1.conv1.weight", {6, 4, 3, 3}}, {"down.0.block.1.conv1.bias", {6}},
      {"down.0.block.1.temb_proj.weight", {6, 8}}, {"down.0.block.1.temb_proj.bias", {6}},
      {"down.0.block.1.norm2.weight", {6}}, {"down.0.block.1.norm2.bias", {6}},
      {"down.0.block.1.conv2.weight", {6, 6, 3, 3}}, {"down.0.block.1.conv2.bias", {6}},
      {"down.0.block.1.nin_shortcut.weight", {6, 4, 1, 1}}, {"down.0.block.1.nin_shortcut.bias", {6}},
      {"down.1.block.0.norm1.weight", {6}}, {"down.1.block.0.norm1.bias", {6}},
      {"down.1.block.0.conv1.weight", {6, 6, 3, 3}}, {"down.1.block.0.conv1.bias", {6}},
      {"down.1.block.0.norm2.weight", {6}}, {"down.1.block.0.norm2.bias", {6}},
      {"down.1.block.0.conv2.weight", {6, 6, 3, 3}}, {"down.1.block.0.conv2.bias", {6}},
  };
  Net net(context());
  const NamedParameters named = net.namedParameters();
  ASSERT_EQ(named.size(), expected.size());
  for (std::size_t i = 0; i < named.size(); ++i) {
    EXPECT_EQ(named[i].first, expected[i].first);
    EXPECT_EQ(named[i].second->value.shape(), expected[i].second) << named[i].first;
  }
}

// A 3D block on a volume one voxel deep equals the 2D block (checked against PyTorch) whose 3x3 kernels
// are the middle depth slices of the 3D block's 3x3x3 ones.
TEST_F(ModulesTest, ResBlock3dOnOneSliceEqualsResBlock2d) {
  const ResBlockOptions options3d{.dims = 3, .inChannels = 2, .outChannels = 4, .tembChannels = 8, .groups = 2};
  ResBlockOptions options2d = options3d;
  options2d.dims = 2;
  ResBlock block3d(context(), options3d), block2d(context(), options2d);
  block3d.initialize(1);
  const NamedParameters p3 = block3d.namedParameters(), p2 = block2d.namedParameters();
  ASSERT_EQ(p3.size(), p2.size());
  for (std::size_t i = 0; i < p3.size(); ++i) {
    std::vector<float> values = p3[i].second->value.download();
    const Shape& shape = p3[i].second->value.shape();
    if (shape.size() == 5 && shape[2] == 3) {  // [o, i, 3, 3, 3] -> [o, i, 3, 3] at depth 1
      std::vector<float> middle;
      for (int64_t oi = 0; oi < shape[0] * shape[1]; ++oi)
        for (int64_t hw = 0; hw < 9; ++hw) middle.push_back(values[static_cast<std::size_t>(oi * 27 + 9 + hw)]);
      values = middle;
    }
    p2[i].second->value.upload(values);
  }
  std::vector<float> xValues;
  const Tensor x = randomTensor(context(), {2, 2, 1, 4, 5}, 1, -1, 1, &xValues);
  const Var temb = variable(randomTensor(context(), {2, 8}, 2));
  Stream stream(context());
  Tape tape(stream);
  const Var y3 = block3d.forward(tape, variable(x), temb);
  const Var y2 = block2d.forward(tape, variable(Tensor::fromHost(context(), {2, 2, 4, 5}, xValues)), temb);
  stream.submit();
  EXPECT_EQ(y3->value.shape(), (Shape{2, 4, 1, 4, 5}));
  EXPECT_TRUE(allClose(y3->value, y2->value.download(), {1e-5, 1e-5}));
}

// With dropout active (training, p > 0) the block cannot read its second norm inside conv2 and runs the norm,
// the dropout and the convolution one after the other: the same as composing them by hand.
TEST_F(ModulesTest, ResBlockWithActiveDropoutIsTheComposition) {
  ResBlock block(context(), {.inChannels = 2, .groups = 2, .dropout = 0.5f, .dropoutSeed = 9});
  block.initialize(3);
  const NamedParameters p = block.namedParameters();
  auto parameter = [&](const std::string& name) {
    for (const auto& [n, v] : p)
      if (n == name) return v;
    throw Error("no parameter " + name);
  };
  const Var x = variable(randomTensor(context(), {1, 2, 5, 6}, 4));
  const ops::ConvParams same{1, 1};
  Stream stream(context());
  Tape tape(stream);
  const Var y = block.forward(tape, x);
  const Var h = fn::conv2d(tape, fn::groupNormSilu(tape, x, parameter("norm1.weight"), parameter("norm1.bias"), 2, 1e-6f),
                           parameter("conv1.weight"), parameter("conv1.bias"), same);
  const Var dropped = fn::dropout(tape, fn::groupNormSilu(tape, h, parameter("norm2.weight"), parameter("norm2.bias"), 2, 1e-6f),
                                  0.5f, uint64_t{9} << 32, true);
  const Var expected = fn::add(tape, x, fn::conv2d(tape, dropped, parameter("conv2.weight"), parameter("conv2.bias"), same));
  stream.submit();
  EXPECT_TRUE(allClose(y->value, expected->value.download(), {1e-6, 1e-6}));
}

// A block given SiLU(temb) (as the DDPM UNet gives each of its blocks the one activated embedding) computes
// what it computes from temb, bit for bit.
TEST_F(ModulesTest, ResBlockOfTheActivatedEmbeddingEqualsTheBlockOfTheEmbedding) {
  ResBlock block(context(), {.inChannels = 2, .outChannels = 4, .tembChannels = 8, .groups = 2});
  block.initialize(5);
  const Var x = variable(randomTensor(context(), {2, 2, 5, 6}, 6), true);
  const Var temb = variable(randomTensor(context(), {2, 8}, 7), true);
  Stream stream(context());
  Tape tape(stream);
  const Var fromTemb = block.forward(tape, x, temb);
  const Var fromActivated = block.forwardOfActivatedEmbedding(tape, x, fn::silu(tape, temb));
  stream.submit();
  EXPECT_EQ(fromTemb->value.download(), fromActivated->value.download());
  ResBlock plain(context(), {.inChannels = 2, .groups = 2});
  EXPECT_THROW(plain.forwardOfActivatedEmbedding(tape, x, temb), Error);
  EXPECT_THROW(block.forwardOfActivatedEmbedding(tape, x, nullptr), Error);
}

TEST_F(ModulesTest, ResBlockChecksItsEmbeddingAndGroups) {
  Stream stream(context());
  Tape tape(stream);
  const Var x = variable(randomTensor(context(), {1, 2, 4, 4}, 1));
  ResBlock plain(context(), {.inChannels = 2, .groups = 2});
  EXPECT_THROW(plain.forward(tape, x, variable(randomTensor(context(), {1, 8}, 2))), Error);
  ResBlock withEmbedding(context(), {.inChannels = 2, .tembChannels = 8, .groups = 2});
  EXPECT_THROW(withEmbedding.forward(tape, x), Error);
  EXPECT_THROW(ResBlock(context(), {.inChannels = 6, .outChannels = 4, .groups = 4}), Error);
}

}  // namespace
}  // namespace smokesvd::testing

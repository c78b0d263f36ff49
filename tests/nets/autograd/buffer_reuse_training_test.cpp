#include <gtest/gtest.h>

#include <bit>

#include "nets/functional/losses.h"
#include "nets/modules/activation.h"
#include "nets/modules/conv.h"
#include "nets/optim/adam.h"
#include "runtime/context.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using namespace modules;

// A forward + backward + Adam step of a conv3d stack, recorded once with and once without buffer reuse
// and each submitted several times, in a context with synchronization validation: reuse must change
// nothing but the memory the recording holds.
class BufferReuseTraining : public ::testing::Test {
 protected:
  static Context& context() {
    static Context context([] {
      ContextOptions options;
      options.validation = true;
      options.synchronizationValidation = true;
      return options;
    }());
    return context;
  }
  void TearDown() override {
    for (const std::string& message : context().takeValidationMessages())
      ADD_FAILURE() << "validation layer: " << message;
  }

  struct Run {
    std::vector<std::vector<float>> parameters;
    std::vector<float> loss;
    StreamMemory memory;
  };

  static Run train(bool reuse, int submissions) {
    Context& c = context();
    auto net = std::make_shared<Sequential>();
    net->add(std::make_shared<Conv>(c, 3, 2, 4, 3, ConvOptions{1, 1}));
    for (int layer = 0; layer < 3; ++layer) {
      net->add(std::make_shared<Activation>(ActivationKind::SiLU));
      net->add(std::make_shared<Conv>(c, 3, 4, layer < 2 ? 4 : 1, 3, ConvOptions{1, 1}));
    }
    net->initialize(7);
    const Var x = variable(randomTensor(c, {2, 2, 6, 7, 5}, 8));
    const Var target = variable(randomTensor(c, {2, 1, 6, 7, 5}, 9));
    optim::Adam adam(c, net->namedParameters(), optim::AdamOptions{});

    Run run;
    Stream stream(c, {.reuseBuffers = reuse});
    {
      Tape tape(stream);
      const Var loss = fn::mseLoss(tape, net->forward(tape, x), target);
      tape.backward(loss);
      adam.step(stream);
      run.memory = stream.memory();
      for (int step = 0; step < submissions; ++step) {
        stream.submit();
        run.loss.push_back(loss->value.download()[0]);
      }
    }
    for (const auto& [name, parameter] : net->namedParameters()) run.parameters.push_back(parameter->value.download());
    return run;
  }
};

std::vector<uint32_t> bits(const std::vector<float>& values) {
  std::vector<uint32_t> out;
  for (float v : values) out.push_back(std::bit_cast<uint32_t>(v));
  return out;
}

TEST_F(BufferReuseTraining, ReuseChangesNothingButThePeakMemory) {
  const Run plain = train(false, 4), reused = train(true, 4);
  EXPECT_EQ(plain.memory.reusedBuffers, 0u);
  EXPECT_GT(reused.memory.reusedBuffers, 0u);
  EXPECT_LT(reused.memory.heldBytes, plain.memory.heldBytes * 3 / 4)
      << reused.memory.heldBytes << " bytes held with reuse, " << plain.memory.heldBytes << " without";
  EXPECT_EQ(reused.memory.bytesWithoutReuse(), plain.memory.heldBytes);
  EXPECT_EQ(bits(reused.loss), bits(plain.loss));
  EXPECT_GT(plain.loss.front(), plain.loss.back());  // the steps do train
  ASSERT_EQ(reused.parameters.size(), plain.parameters.size());
  for (std::size_t p = 0; p < plain.parameters.size(); ++p)
    EXPECT_EQ(bits(reused.parameters[p]), bits(plain.parameters[p])) << "parameter " << p;
}

}  // namespace
}  // namespace smokesvd::testing

// Differential operators and the MAC <-> centred conversion against plain CPU references, and their
// adjoints against finite differences in double, on small odd-sized grids.
#include "pipeline/physics/differential.h"

#include <gtest/gtest.h>

#include <array>
#include <functional>

#include "pipeline/physics/grid.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using physics::Staggering;
using Cell = std::array<int, 3>;

const GridSize kGrid{.x = 7, .y = 5, .z = 6};

int size(int axis) { return static_cast<int>(axis == 0 ? kGrid.x : axis == 1 ? kGrid.y : kGrid.z); }
int cells() { return static_cast<int>(kGrid.cells()); }
int index(const Cell& c) { return (c[2] * size(1) + c[1]) * size(0) + c[0]; }
bool inGrid(const Cell& c) {
  for (int d = 0; d < 3; ++d)
    if (c[d] < 0 || c[d] >= size(d)) return false;
  return true;
}
Cell shifted(Cell c, int axis, int by) {
  c[axis] += by;
  return c;
}

template <typename Body>
void forEachCell(Body body) {
  for (int k = 0; k < size(2); ++k)
    for (int j = 0; j < size(1); ++j)
      for (int i = 0; i < size(0); ++i) body(Cell{i, j, k});
}

// Plain references in double. u is planar [3, cells].
double at(std::span<const double> u, int plane, const Cell& c) {
  return inGrid(c) ? u[plane * cells() + index(c)] : 0.0;
}

double difference(std::span<const double> u, int plane, const Cell& c, int d) {
  if (c[d] == 0) return at(u, plane, shifted(c, d, 1)) - at(u, plane, c);
  if (c[d] == size(d) - 1) return at(u, plane, c) - at(u, plane, shifted(c, d, -1));
  return 0.5 * (at(u, plane, shifted(c, d, 1)) - at(u, plane, shifted(c, d, -1)));
}

std::vector<double> macToCentred(std::span<const double> mac) {
  std::vector<double> out(mac.size());
  forEachCell([&](const Cell& c) {
    for (int d = 0; d < 3; ++d) out[d * cells() + index(c)] = 0.5 * (at(mac, d, c) + at(mac, d, shifted(c, d, 1)));
  });
  return out;
}

std::vector<double> centredToMac(std::span<const double> centred) {
  std::vector<double> out(centred.size());
  forEachCell([&](const Cell& c) {
    for (int d = 0; d < 3; ++d)
      out[d * cells() + index(c)] = 0.5 * (at(centred, d, shifted(c, d, -1)) + at(centred, d, c));
  });
  return out;
}

std::vector<double> divergence(std::span<const double> u, Staggering staggering) {
  std::vector<double> out(static_cast<std::size_t>(cells()));
  forEachCell([&](const Cell& c) {
    double sum = 0;
    for (int d = 0; d < 3; ++d)
      sum += staggering == Staggering::Mac ? at(u, d, shifted(c, d, 1)) - at(u, d, c) : difference(u, d, c, d);
    out[index(c)] = sum;
  });
  return out;
}

std::vector<double> curl(std::span<const double> u) {
  std::vector<double> out(u.size());
  forEachCell([&](const Cell& c) {
    out[0 * cells() + index(c)] = difference(u, 2, c, 1) - difference(u, 1, c, 2);
    out[1 * cells() + index(c)] = difference(u, 0, c, 2) - difference(u, 2, c, 0);
    out[2 * cells() + index(c)] = difference(u, 1, c, 0) - difference(u, 0, c, 1);
  });
  return out;
}

std::vector<double> gradientNorm(std::span<const double> u) {
  std::vector<double> out(static_cast<std::size_t>(cells()));
  forEachCell([&](const Cell& c) {
    double sum = 0;
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) sum += difference(u, k, c, d) * difference(u, k, c, d);
    out[index(c)] = sum;
  });
  return out;
}

class DifferentialTest : public GpuTest {
 protected:
  // Runs `forward` on a random velocity and compares with `reference`; then runs `backward` on a random
  // upstream gradient and compares with finite differences of the reference.
  void check(const std::function<std::vector<double>(std::span<const double>)>& reference, const Shape& outShape,
             const std::function<void(Stream&, const Tensor&, const Tensor&)>& forward,
             const std::function<void(Stream&, const Tensor&, const Tensor&, const Tensor&)>& backward, uint64_t seed) {
    std::vector<float> u;
    Tensor velocity = randomTensor(context(), kGrid.vector(), seed, -1, 1, &u);
    std::vector<float> g;
    Tensor gradOut = randomTensor(context(), outShape, seed + 1, -1, 1, &g);
    Tensor out = poisonedTensor(context(), outShape);
    Tensor gradVelocity = poisonedTensor(context(), kGrid.vector());
    Stream stream(context());
    forward(stream, velocity, out);
    backward(stream, velocity, gradOut, gradVelocity);
    stream.submit();
    const std::vector<double> exact = toDouble(u);
    EXPECT_TRUE(allClose(out, reference(exact), {1e-5, 1e-5}));
    EXPECT_TRUE(allClose(gradVelocity, numericVjp(reference, exact, toDouble(g)), {1e-5, 1e-5}));
  }
};

TEST_F(DifferentialTest, MacToCentredAndBack) {
  check(
      macToCentred, kGrid.vector(), physics::macToCentred,
      [](Stream& s, const Tensor&, const Tensor& g, const Tensor& out) { physics::centredToMac(s, g, out); }, 1);
  check(
      centredToMac, kGrid.vector(), physics::centredToMac,
      [](Stream& s, const Tensor&, const Tensor& g, const Tensor& out) { physics::macToCentred(s, g, out); }, 2);
}

// A linear velocity field is reproduced exactly by the face averages: MAC samples give the centred
// samples and back, wherever the averages stay inside the grid.
TEST_F(DifferentialTest, MacCentredRoundTripIsExactForLinearFields) {
  const std::array<std::array<double, 4>, 3> coefficients{
      {{0.3, 0.1, -0.2, 0.05}, {-0.4, 0.02, 0.3, -0.1}, {0.2, -0.15, 0.07, 0.12}}};
  auto linear = [&](int d, double x, double y, double z) {
    return coefficients[d][0] + coefficients[d][1] * x + coefficients[d][2] * y + coefficients[d][3] * z;
  };
  std::vector<float> mac(static_cast<std::size_t>(3 * cells()));
  forEachCell([&](const Cell& c) {
    for (int d = 0; d < 3; ++d) {
      std::array<double, 3> p{c[0] + 0.5, c[1] + 0.5, c[2] + 0.5};
      p[d] -= 0.5;
      mac[d * cells() + index(c)] = static_cast<float>(linear(d, p[0], p[1], p[2]));
    }
  });
  Tensor macTensor = Tensor::fromHost(context(), kGrid.vector(), mac);
  Tensor centred = poisonedTensor(context(), kGrid.vector());
  Tensor back = poisonedTensor(context(), kGrid.vector());
  Stream stream(context());
  physics::macToCentred(stream, macTensor, centred);
  physics::centredToMac(stream, centred, back);
  stream.submit();
  const std::vector<float> centredValues = centred.download();
  const std::vector<float> backValues = back.download();
  forEachCell([&](const Cell& c) {
    for (int d = 0; d < 3; ++d) {
      const int i = d * cells() + index(c);
      if (c[d] < size(d) - 1) {
        EXPECT_NEAR(centredValues[i], linear(d, c[0] + 0.5, c[1] + 0.5, c[2] + 0.5), 1e-5) << "centred " << d;
      }
      if (c[d] >= 1 && c[d] < size(d) - 1) {
        EXPECT_NEAR(backValues[i], mac[i], 1e-5) << "round trip " << d;
      }
    }
  });
}

TEST_F(DifferentialTest, DivergenceOfMacVelocity) {
  check([](std::span<const double> u) { return divergence(u, Staggering::Mac); }, kGrid.volume(),
        [](Stream& s, const Tensor& u, const Tensor& out) { physics::divergence(s, u, Staggering::Mac, out); },
        [](Stream& s, const Tensor&, const Tensor& g, const Tensor& out) {
          physics::divergenceBackward(s, Staggering::Mac, g, out);
        },
        3);
}

TEST_F(DifferentialTest, DivergenceOfCentredVelocity) {
  check([](std::span<const double> u) { return divergence(u, Staggering::Centred); }, kGrid.volume(),
        [](Stream& s, const Tensor& u, const Tensor& out) { physics::divergence(s, u, Staggering::Centred, out); },
        [](Stream& s, const Tensor&, const Tensor& g, const Tensor& out) {
          physics::divergenceBackward(s, Staggering::Centred, g, out);
        },
        4);
}

TEST_F(DifferentialTest, Curl) {
  check(
      curl, kGrid.vector(), physics::curl,
      [](Stream& s, const Tensor&, const Tensor& g, const Tensor& out) { physics::curlBackward(s, g, out); }, 5);
}

TEST_F(DifferentialTest, GradientNormSquared) {
  check(gradientNorm, kGrid.volume(), physics::gradientNormSquared, physics::gradientNormSquaredBackward, 6);
}

TEST_F(DifferentialTest, VelocityLayoutConversions) {
  std::vector<float> interleaved;
  Tensor file = randomTensor(context(), {kGrid.z, kGrid.y, kGrid.x, 3}, 7, -1, 1, &interleaved);
  Tensor planar = poisonedTensor(context(), kGrid.vector());
  Tensor back = poisonedTensor(context(), file.shape());
  Stream stream(context());
  physics::interleavedToPlanar(stream, file, planar);
  physics::planarToInterleaved(stream, planar, back);
  stream.submit();
  std::vector<float> expected(interleaved.size());
  for (int cell = 0; cell < cells(); ++cell)
    for (int d = 0; d < 3; ++d) expected[d * cells() + cell] = interleaved[3 * cell + d];
  EXPECT_TRUE(allClose(planar, expected, {0, 0}));
  EXPECT_TRUE(allClose(back, interleaved, {0, 0}));
}

TEST_F(DifferentialTest, RejectsMismatchedShapes) {
  Tensor velocity(context(), kGrid.vector());
  Tensor wrong(context(), {kGrid.z, kGrid.y, kGrid.x + 1});
  Stream stream(context());
  EXPECT_THROW(physics::divergence(stream, velocity, Staggering::Mac, wrong), Error);
  EXPECT_THROW(physics::curl(stream, velocity, wrong), Error);
}

}  // namespace
}  // namespace smokesvd::testing

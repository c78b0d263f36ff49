#include "tests/pipeline/eval/metric_reference.h"

#include <cmath>

namespace smokesvd::testing {
namespace {

struct Grid {
  int x, y, z;
  std::size_t cell(int i, int j, int k) const { return (static_cast<std::size_t>(k) * y + j) * x + i; }
  std::size_t cells() const { return static_cast<std::size_t>(x) * y * z; }
  int extent(int axis) const { return axis == 0 ? x : axis == 1 ? y : z; }
};

double face(const std::vector<float>& u, const Grid& g, int d, int i, int j, int k) {
  if (i >= g.x || j >= g.y || k >= g.z) return 0;
  return u[d * g.cells() + g.cell(i, j, k)];
}

// The cell-centred velocity ½(u_d(c) + u_d(c + e_d)) and the MAC divergence per cell.
void centredAndDivergence(const std::vector<float>& u, const Grid& g, std::vector<double>& centred, std::vector<double>& divergence) {
  centred.assign(3 * g.cells(), 0.0);
  divergence.assign(g.cells(), 0.0);
  for (int k = 0; k < g.z; ++k)
    for (int j = 0; j < g.y; ++j)
      for (int i = 0; i < g.x; ++i) {
        const int up[3][3] = {{i + 1, j, k}, {i, j + 1, k}, {i, j, k + 1}};
        for (int d = 0; d < 3; ++d) {
          const double low = face(u, g, d, i, j, k), high = face(u, g, d, up[d][0], up[d][1], up[d][2]);
          divergence[g.cell(i, j, k)] += high - low;
          centred[d * g.cells() + g.cell(i, j, k)] = 0.5 * (low + high);
        }
      }
}

}  // namespace

double referenceMse(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (static_cast<double>(a[i]) - b[i]) * (static_cast<double>(a[i]) - b[i]);
  return sum / static_cast<double>(a.size());
}

double referencePsnr(double mse) { return mse <= 1e-10 ? 100.0 : 10.0 * std::log10(1.0 / mse); }

double referenceSsim(const std::vector<float>& a, const std::vector<float>& b, int width, int height) {
  double weights[11][11], total = 0;
  for (int i = 0; i < 11; ++i)
    for (int j = 0; j < 11; ++j) total += weights[i][j] = std::exp(-((i - 5) * (i - 5) + (j - 5) * (j - 5)) / (2 * 1.5 * 1.5));
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  double sum = 0;
  int count = 0;
  for (int r = 0; r + 11 <= height; ++r)
    for (int c = 0; c + 11 <= width; ++c) {
      double ma = 0, mb = 0, aa = 0, bb = 0, ab = 0;
      for (int i = 0; i < 11; ++i)
        for (int j = 0; j < 11; ++j) {
          const std::size_t p = static_cast<std::size_t>((r + i) * width + c + j);
          const double w = weights[i][j] / total, x = a[p], y = b[p];
          ma += w * x;
          mb += w * y;
          aa += w * x * x;
          bb += w * y * y;
          ab += w * x * y;
        }
      const double va = aa - ma * ma, vb = bb - mb * mb, cov = ab - ma * mb;
      sum += (2 * ma * mb + c1) * (2 * cov + c2) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      ++count;
    }
  return sum / count;
}

double referenceMeanAbsDivergence(const std::vector<float>& u, int x, int y, int z) {
  const Grid g{x, y, z};
  std::vector<double> centred, divergence;
  centredAndDivergence(u, g, centred, divergence);
  double sum = 0;
  for (double d : divergence) sum += std::abs(d);
  return sum / static_cast<double>(g.cells());
}

double referenceMeanGradientSquared(const std::vector<float>& u, int x, int y, int z) {
  const Grid g{x, y, z};
  std::vector<double> centred, divergence;
  centredAndDivergence(u, g, centred, divergence);
  double sum = 0;
  for (int k = 0; k < g.z; ++k)
    for (int j = 0; j < g.y; ++j)
      for (int i = 0; i < g.x; ++i)
        for (int comp = 0; comp < 3; ++comp)
          for (int d = 0; d < 3; ++d) {
            const int c[3] = {i, j, k};
            const int n = g.extent(d);
            auto at = [&](int index) {
              int p[3] = {c[0], c[1], c[2]};
              p[d] = index;
              return centred[comp * g.cells() + g.cell(p[0], p[1], p[2])];
            };
            const double diff = n == 1 ? 0.0
                                : c[d] == 0 ? at(1) - at(0)
                                : c[d] == n - 1 ? at(n - 1) - at(n - 2)
                                                : 0.5 * (at(c[d] + 1) - at(c[d] - 1));
            sum += diff * diff;
          }
  return sum / static_cast<double>(g.cells());
}

}  // namespace smokesvd::testing

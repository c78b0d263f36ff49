#include "tests/sim/sim_reference.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace smokesvd::testing::sim {

Cell step(Cell c, int axis, int64_t amount) {
  if (axis == 0) c.i += amount;
  else if (axis == 1) c.j += amount;
  else c.k += amount;
  return c;
}

std::vector<float> randomFlags(const GridSize& grid, uint64_t seed, double obstacleShare, double emptyShare) {
  std::mt19937_64 generator(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<float> flags(static_cast<std::size_t>(grid.cells()));
  std::size_t index = 0;
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i) {
        const bool wall = i == 0 || j == 0 || k == 0 || i == grid.x - 1 || j == grid.y - 1 || k == grid.z - 1;
        const double u = uniform(generator);
        flags[index++] = wall || u < obstacleShare ? 2.0f : (u < obstacleShare + emptyShare ? 4.0f : 1.0f);
      }
  return flags;
}

Field widen(const std::vector<float>& values) { return Field(values.begin(), values.end()); }

Field divergence(const FlagView& flags, const Field& velocity) {
  const int64_t cells = flags.grid().cells();
  Field div(static_cast<std::size_t>(cells), 0.0);
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    if (!flags.fluid(c)) continue;
    double sum = 0;
    for (int a = 0; a < 3; ++a) {
      if (!flags.obstacle(step(c, a, -1))) sum -= velocity[a * cells + index];
      const Cell upper = step(c, a, 1);
      if (!flags.obstacle(upper)) sum += velocity[a * cells + flags.index(upper)];
    }
    div[index] = sum;
  }
  return div;
}

Field laplacian(const FlagView& flags, const Field& x) {
  const int64_t cells = flags.grid().cells();
  Field result(static_cast<std::size_t>(cells), 0.0);
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    if (!flags.fluid(c)) continue;
    double sum = 0;
    for (int a = 0; a < 3; ++a)
      for (int side : {-1, 1}) {
        const Cell n = step(c, a, side);
        if (!flags.obstacle(n)) sum += x[index] - (flags.fluid(n) ? x[flags.index(n)] : 0.0);
      }
    result[index] = sum;
  }
  return result;
}

std::vector<int> nonObstacleNeighbours(const FlagView& flags) {
  const int64_t cells = flags.grid().cells();
  std::vector<int> count(static_cast<std::size_t>(cells), 0);
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    for (int a = 0; a < 3; ++a)
      for (int side : {-1, 1}) count[index] += flags.obstacle(step(c, a, side)) ? 0 : 1;
  }
  return count;
}

Field jacobiSweep(const FlagView& flags, const Field& rhs, const Field& x, double weight) {
  const Field ax = laplacian(flags, x);
  const std::vector<int> diagonal = nonObstacleNeighbours(flags);
  Field result(x.size(), 0.0);
  for (std::size_t index = 0; index < x.size(); ++index) {
    if (!flags.fluid(flags.cell(static_cast<int64_t>(index))) || diagonal[index] == 0) continue;
    result[index] = x[index] + weight * (rhs[index] - ax[index]) / diagonal[index];
  }
  return result;
}

Field restrictResidual(const FlagView& fine, const Field& rhs, const Field& x, const FlagView& coarse, double scale) {
  const Field ax = laplacian(fine, x);
  Field result(static_cast<std::size_t>(coarse.grid().cells()), 0.0);
  for (int64_t index = 0; index < coarse.grid().cells(); ++index) {
    const Cell C = coarse.cell(index);
    if (!coarse.fluid(C)) continue;
    double sum = 0;
    for (int child = 0; child < 8; ++child) {
      const Cell f{2 * C.i + (child & 1), 2 * C.j + ((child >> 1) & 1), 2 * C.k + (child >> 2)};
      if (fine.fluid(f)) sum += rhs[fine.index(f)] - ax[fine.index(f)];
    }
    result[index] = scale * sum;
  }
  return result;
}

std::vector<float> stencilMasks(const FlagView& flags) {
  const int64_t cells = flags.grid().cells();
  std::vector<float> masks(static_cast<std::size_t>(cells));
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    uint32_t mask = (flags.fluid(c) ? 1u : 0u) | (flags.obstacle(c) ? 0u : 2u);
    for (int n = 0; n < 6; ++n) {
      const Cell neighbour = step(c, n / 2, n % 2 == 0 ? -1 : 1);
      if (!flags.obstacle(neighbour)) mask |= 4u << n;
      if (flags.fluid(neighbour)) mask |= 256u << n;
    }
    masks[index] = static_cast<float>(mask);
  }
  return masks;
}

std::vector<float> coarsenFlags(const FlagView& fine, const GridSize& coarse) {
  std::vector<float> result(static_cast<std::size_t>(coarse.cells()));
  for (int64_t index = 0; index < coarse.cells(); ++index) {
    const Cell C{index % coarse.x, (index / coarse.x) % coarse.y, index / (coarse.x * coarse.y)};
    bool anyEmpty = false, anyFluid = false;
    for (int child = 0; child < 8; ++child) {
      const Cell f{2 * C.i + (child & 1), 2 * C.j + ((child >> 1) & 1), 2 * C.k + (child >> 2)};
      if (!fine.inside(f)) continue;
      anyEmpty = anyEmpty || (!fine.obstacle(f) && !fine.fluid(f));
      anyFluid = anyFluid || fine.fluid(f);
    }
    result[index] = anyEmpty ? 4.0f : (anyFluid ? 1.0f : 2.0f);
  }
  return result;
}

Field prolongAdd(const FlagView& fine, const Field& x, const Field& coarse, const GridSize& coarseGrid) {
  Field result = x;
  for (int64_t index = 0; index < fine.grid().cells(); ++index) {
    const Cell f = fine.cell(index);
    if (!fine.fluid(f)) continue;
    result[index] += coarse[f.i / 2 + coarseGrid.x * (f.j / 2 + coarseGrid.y * (f.k / 2))];
  }
  return result;
}

Field correctVelocity(const FlagView& flags, const Field& pressure, const Field& velocity) {
  const int64_t cells = flags.grid().cells();
  Field result = velocity;
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    for (int a = 0; a < 3; ++a) {
      const Cell m = step(c, a, -1);
      double& u = result[a * cells + index];
      if (flags.obstacle(c) || flags.obstacle(m)) {
        u = 0;
      } else if (flags.fluid(c) || flags.fluid(m)) {
        const double pc = flags.fluid(c) ? pressure[index] : 0.0;
        const double pm = flags.fluid(m) ? pressure[flags.index(m)] : 0.0;
        u -= pc - pm;
      }
    }
  }
  return result;
}

bool forceActs(const FlagView& flags, Cell c, int axis) {
  const Cell m = step(c, axis, -1);
  return !flags.obstacle(c) && !flags.obstacle(m) && (flags.fluid(c) || flags.fluid(m));
}

Field addBuoyancy(const FlagView& flags, const Field& density, const Field& temperature, const Field& velocity,
                  const Vec3d& uniform, const Vec3d& perDensity, const Vec3d& perTemperature, double dt) {
  const int64_t cells = flags.grid().cells();
  Field result = velocity;
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    for (int a = 0; a < 3; ++a) {
      if (!forceActs(flags, c, a)) continue;
      const int64_t m = flags.index(step(c, a, -1));
      result[a * cells + index] += dt * (uniform[a] + perDensity[a] * 0.5 * (density[index] + density[m]) +
                                         perTemperature[a] * 0.5 * (temperature[index] + temperature[m]));
    }
  }
  return result;
}

Field addForceField(const FlagView& flags, const Field& force, const Field& velocity, double dt) {
  const int64_t cells = flags.grid().cells();
  Field result = velocity;
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    for (int a = 0; a < 3; ++a) {
      if (!forceActs(flags, c, a)) continue;
      const int64_t m = flags.index(step(c, a, -1));
      result[a * cells + index] += dt * 0.5 * (force[a * cells + index] + force[a * cells + m]);
    }
  }
  return result;
}

namespace {

bool interior(const GridSize& g, Cell c) {
  return c.i > 0 && c.j > 0 && c.k > 0 && c.i < g.x - 1 && c.j < g.y - 1 && c.k < g.z - 1;
}

}  // namespace

Field vorticityField(const GridSize& grid, const Field& velocity) {
  const int64_t cells = grid.cells();
  auto index = [&](Cell c) { return c.i + grid.x * (c.j + grid.y * c.k); };
  // Centred velocity, 0 on the outer layer (mantaflow's GetCentered with bnd = 1).
  Field centred(static_cast<std::size_t>(3 * cells), 0.0);
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i) {
        const Cell c{i, j, k};
        if (!interior(grid, c)) continue;
        for (int a = 0; a < 3; ++a)
          centred[a * cells + index(c)] = 0.5 * (velocity[a * cells + index(c)] + velocity[a * cells + index(step(c, a, 1))]);
      }
  auto derivative = [&](int component, int along, Cell c) {
    return 0.5 * (centred[component * cells + index(step(c, along, 1))] -
                  centred[component * cells + index(step(c, along, -1))]);
  };
  Field result(static_cast<std::size_t>(4 * cells), 0.0);
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i) {
        const Cell c{i, j, k};
        if (!interior(grid, c)) continue;
        const Vec3d omega{derivative(2, 1, c) - derivative(1, 2, c), derivative(0, 2, c) - derivative(2, 0, c),
                          derivative(1, 0, c) - derivative(0, 1, c)};
        for (int a = 0; a < 3; ++a) result[a * cells + index(c)] = omega[a];
        result[3 * cells + index(c)] = std::sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
      }
  return result;
}

Field addVorticityConfinement(const FlagView& flags, const Field& vorticity, const Field& velocity, double strength,
                              double dt) {
  const GridSize& grid = flags.grid();
  const int64_t cells = grid.cells();
  auto force = [&](Cell c) -> Vec3d {
    if (!interior(grid, c)) return {0, 0, 0};
    Vec3d gradient;
    for (int a = 0; a < 3; ++a)
      gradient[a] = 0.5 * (vorticity[3 * cells + flags.index(step(c, a, 1))] - vorticity[3 * cells + flags.index(step(c, a, -1))]);
    const double norm = std::sqrt(gradient[0] * gradient[0] + gradient[1] * gradient[1] + gradient[2] * gradient[2]);
    if (norm <= 1e-20) return {0, 0, 0};
    for (double& g : gradient) g /= norm;
    const int64_t at = flags.index(c);
    const Vec3d w{vorticity[at], vorticity[cells + at], vorticity[2 * cells + at]};
    return {strength * (gradient[1] * w[2] - gradient[2] * w[1]), strength * (gradient[2] * w[0] - gradient[0] * w[2]),
            strength * (gradient[0] * w[1] - gradient[1] * w[0])};
  };
  Field result = velocity;
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    for (int a = 0; a < 3; ++a) {
      if (!forceActs(flags, c, a)) continue;
      result[a * cells + index] += dt * 0.5 * (force(c)[a] + force(step(c, a, -1))[a]);
    }
  }
  return result;
}

double maxAbs(const Field& values) {
  double m = 0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

double dot(const Field& a, const Field& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += a[i] * b[i];
  return sum;
}

}  // namespace smokesvd::testing::sim

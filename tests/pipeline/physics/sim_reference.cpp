#include "tests/pipeline/physics/sim_reference.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace smokesvd::testing::ref {

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

Field vorticityForce(const GridSize& grid, const Field& vorticity, double strength) {
  const int64_t cells = grid.cells();
  auto index = [&](Cell c) { return c.i + grid.x * (c.j + grid.y * c.k); };
  Field result(static_cast<std::size_t>(3 * cells), 0.0);
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i) {
        const Cell c{i, j, k};
        if (!interior(grid, c)) continue;
        Vec3d gradient;
        for (int a = 0; a < 3; ++a)
          gradient[a] = 0.5 * (vorticity[3 * cells + index(step(c, a, 1))] - vorticity[3 * cells + index(step(c, a, -1))]);
        const double norm = std::sqrt(gradient[0] * gradient[0] + gradient[1] * gradient[1] + gradient[2] * gradient[2]);
        if (norm <= 1e-20) continue;
        for (double& g : gradient) g /= norm;
        const int64_t at = index(c);
        const Vec3d w{vorticity[at], vorticity[cells + at], vorticity[2 * cells + at]};
        result[at] = strength * (gradient[1] * w[2] - gradient[2] * w[1]);
        result[cells + at] = strength * (gradient[2] * w[0] - gradient[0] * w[2]);
        result[2 * cells + at] = strength * (gradient[0] * w[1] - gradient[1] * w[0]);
      }
  return result;
}

Field addVorticityConfinement(const FlagView& flags, const Field& vorticity, const Field& velocity, double strength,
                              double dt) {
  return addForceField(flags, vorticityForce(flags.grid(), vorticity, strength), velocity, dt);
}

double sourceCoverage(const physics::SourceState& source, const Vec3d& p) {
  const Vec3d d{p[0] - source.centre[0], p[1] - source.centre[1], p[2] - source.centre[2]};
  auto length3 = [](double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); };
  double sdf = 0;
  if (source.shape == physics::SourceShape::Sphere) {
    sdf = length3(d[0], d[1], d[2]) - source.size[0];
  } else if (source.shape == physics::SourceShape::Box) {
    Vec3d q;
    for (int a = 0; a < 3; ++a) q[a] = std::abs(d[a]) - source.size[a];
    sdf = length3(std::max(q[0], 0.0), std::max(q[1], 0.0), std::max(q[2], 0.0)) +
          std::min(std::max({q[0], q[1], q[2]}), 0.0);
  } else {
    const double axisLength = length3(source.axis[0], source.axis[1], source.axis[2]);
    const Vec3d axis{source.axis[0] / axisLength, source.axis[1] / axisLength, source.axis[2] / axisLength};
    const double along = d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
    const double radial = length3(d[0] - along * axis[0], d[1] - along * axis[1], d[2] - along * axis[2]);
    const double qx = radial - source.size[0], qy = std::abs(along) - source.size[1];
    sdf = std::sqrt(std::max(qx, 0.0) * std::max(qx, 0.0) + std::max(qy, 0.0) * std::max(qy, 0.0)) +
          std::min(std::max(qx, qy), 0.0);
  }
  return std::clamp(0.5 - sdf, 0.0, 1.0);
}

namespace {

double latticeValue(int64_t x, int64_t y, int64_t z, uint32_t seed) {
  uint32_t h = static_cast<uint32_t>(x) * 0x8da6b343u ^ static_cast<uint32_t>(y) * 0xd8163841u ^
               static_cast<uint32_t>(z) * 0xcb1ab31fu ^ seed * 0x9e3779b9u;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return static_cast<double>(h >> 8) / 16777216.0;
}

}  // namespace

double sourceNoise(const physics::SourceState& source, const Vec3d& p) {
  Vec3d x, w;
  std::array<int64_t, 3> base;
  for (int a = 0; a < 3; ++a) {
    x[a] = (p[a] + source.noiseOffset[a]) / std::max(static_cast<double>(source.noiseScale), 1e-3);
    base[a] = static_cast<int64_t>(std::floor(x[a]));
    w[a] = x[a] - static_cast<double>(base[a]);
  }
  double value = 0;
  for (int n = 0; n < 8; ++n) {
    const int dx = n & 1, dy = (n >> 1) & 1, dz = n >> 2;
    const double weight = (dx ? w[0] : 1 - w[0]) * (dy ? w[1] : 1 - w[1]) * (dz ? w[2] : 1 - w[2]);
    value += weight * latticeValue(base[0] + dx, base[1] + dy, base[2] + dz, source.noiseSeed & 0xffffffu);
  }
  return value;
}

void inflowFields(const FlagView& flags, const Field& density, const Field& temperature,
                  const std::vector<physics::SourceState>& sources, double dt, Field& densityInflow,
                  Field& temperatureInflow) {
  const int64_t cells = flags.grid().cells();
  densityInflow.assign(static_cast<std::size_t>(cells), 0.0);
  temperatureInflow.assign(static_cast<std::size_t>(cells), 0.0);
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    if (!flags.fluid(c)) continue;
    const Vec3d p{static_cast<double>(c.i) + 0.5, static_cast<double>(c.j) + 0.5, static_cast<double>(c.k) + 0.5};
    double targetRho = 0, targetT = 0, addedRho = 0, addedT = 0;
    for (const physics::SourceState& s : sources) {
      const double w = sourceCoverage(s, p);
      if (w <= 0) continue;
      const double modulation = s.noiseAmplitude > 0 ? 1 + s.noiseAmplitude * (2 * sourceNoise(s, p) - 1) : 1;
      const double rho = s.density * modulation * w, t = s.temperature * w;
      if (s.mode == physics::InflowMode::Set) {
        targetRho = std::max(targetRho, rho);
        targetT = std::max(targetT, t);
      } else {
        addedRho += dt * rho;
        addedT += dt * t;
      }
    }
    densityInflow[index] = std::max(targetRho - density[index], 0.0) + addedRho;
    temperatureInflow[index] = std::max(targetT - temperature[index], 0.0) + addedT;
  }
}

Field applySourceVelocity(const FlagView& flags, const std::vector<physics::SourceState>& sources,
                          const Field& velocity) {
  const int64_t cells = flags.grid().cells();
  Field result = velocity;
  for (int64_t index = 0; index < cells; ++index) {
    const Cell c = flags.cell(index);
    for (int a = 0; a < 3; ++a) {
      if (flags.obstacle(c) || flags.obstacle(step(c, a, -1))) continue;
      Vec3d p{static_cast<double>(c.i) + 0.5, static_cast<double>(c.j) + 0.5, static_cast<double>(c.k) + 0.5};
      p[a] -= 0.5;
      double& u = result[a * cells + index];
      for (const physics::SourceState& s : sources) {
        if (!s.setsVelocity) continue;
        const double w = sourceCoverage(s, p);
        u = u + (s.velocity[a] - u) * w;
      }
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

}  // namespace smokesvd::testing::ref

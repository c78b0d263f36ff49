#include "tests/pipeline/physics/advect_reference.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "pipeline/physics/grid.h"

namespace smokesvd::testing {
namespace {

using Cell = std::array<int, 3>;

template <typename T>
class Reference {
 public:
  Reference(const AdvectionCase<T>& input, const physics::AdvectionParams& params, AdvectionDiagnostics& diagnostics)
      : in_(input), grid_(input.grid), params_(params), diagnostics_(diagnostics) {}

  std::vector<T> run() {
    const int planes = in_.mac ? 3 : 1;
    const T dt = static_cast<T>(params_.dt);
    std::vector<T> first(in_.field.size(), T(0));
    std::vector<T> out(in_.field.size(), T(0));
    for (int plane = 0; plane < planes; ++plane) {
      forEachInterior([&](const Cell& c) {
        first[at(plane, c)] = sample(in_.field, plane, departure(c, traceVelocity(plane, c), dt));
      });
    }
    if (params_.scheme == physics::AdvectionScheme::SemiLagrangian) {
      out = first;
    } else {
      for (int plane = 0; plane < planes; ++plane)
        forEachInterior([&](const Cell& c) { out[at(plane, c)] = macCormack(first, plane, c); });
    }
    if (!in_.inflow.empty())
      for (std::size_t i = 0; i < out.size(); ++i) out[i] += in_.inflow[i];
    return out;
  }

 private:
  int at(int plane, const Cell& c) const { return plane * grid_.cells() + grid_.index(c[0], c[1], c[2]); }
  int mode(int plane) const { return in_.mac ? plane + 1 : 0; }
  T u(int component, Cell c) const { return in_.velocity[at(component, c)]; }
  static Cell shifted(Cell c, int axis, int by) {
    c[axis] += by;
    return c;
  }
  uint32_t flag(const Cell& c) const { return static_cast<uint32_t>(in_.flags[grid_.index(c[0], c[1], c[2])]); }

  template <typename Body>
  void forEachInterior(Body body) const {
    for (int k = 1; k < grid_.z - 1; ++k)
      for (int j = 1; j < grid_.y - 1; ++j)
        for (int i = 1; i < grid_.x - 1; ++i) body(Cell{i, j, k});
  }

  std::array<T, 3> traceVelocity(int plane, const Cell& c) const {
    std::array<T, 3> v{};
    const int m = mode(plane) - 1;
    for (int d = 0; d < 3; ++d) {
      if (m < 0) {
        v[d] = T(0.5) * (u(d, c) + u(d, shifted(c, d, 1)));
      } else if (d == m) {
        v[d] = u(d, c);
      } else {
        const Cell up = shifted(c, d, 1);
        v[d] = T(0.25) * (u(d, c) + u(d, shifted(c, m, -1)) + u(d, up) + u(d, shifted(up, m, -1)));
      }
    }
    return v;
  }

  static std::array<T, 3> departure(const Cell& c, const std::array<T, 3>& v, T dt) {
    std::array<T, 3> p{};
    for (int d = 0; d < 3; ++d) p[d] = static_cast<T>(c[d]) + T(0.5) - v[d] * dt;
    return p;
  }

  void noteMargin(double distance) { diagnostics_.margin = std::min(diagnostics_.margin, std::abs(distance)); }

  // Trilinear lookup with mantaflow's clamp to the cell centres.
  T sample(const std::vector<T>& data, int plane, const std::array<T, 3>& p) {
    Cell base{};
    std::array<T, 3> upper{};
    for (int d = 0; d < 3; ++d) {
      const int n = grid_.size(d);
      const T q = p[d] - T(0.5);
      base[d] = static_cast<int>(q);
      upper[d] = q - static_cast<T>(base[d]);
      if (q < T(0)) {
        base[d] = 0;
        upper[d] = T(0);
        noteMargin(static_cast<double>(q));
      } else if (base[d] >= n - 1) {
        base[d] = n - 2;
        upper[d] = T(1);
        noteMargin(static_cast<double>(q) - (n - 1));
      } else {
        noteMargin(std::min(static_cast<double>(upper[d]), 1.0 - static_cast<double>(upper[d])));
      }
    }
    auto value = [&](int a, int b, int e) { return data[at(plane, Cell{base[0] + a, base[1] + b, base[2] + e})]; };
    const T s1 = upper[0], s0 = T(1) - s1, t1 = upper[1], t0 = T(1) - t1, f1 = upper[2], f0 = T(1) - f1;
    return ((value(0, 0, 0) * t0 + value(0, 1, 0) * t1) * s0 + (value(1, 0, 0) * t0 + value(1, 1, 0) * t1) * s1) * f0 +
           ((value(0, 0, 1) * t0 + value(0, 1, 1) * t1) * s0 + (value(1, 0, 1) * t0 + value(1, 1, 1) * t1) * s1) * f1;
  }

  bool corrected(int plane, const Cell& c) const {
    if (!(flag(c) & physics::kFluid)) return false;
    const int m = mode(plane) - 1;
    return m < 0 || c[m] == 0 || (flag(shifted(c, m, -1)) & physics::kFluid);
  }

  T macCormack(const std::vector<T>& first, int plane, const Cell& c) {
    const T dt = static_cast<T>(params_.dt);
    const T forward = first[at(plane, c)];
    if (!corrected(plane, c)) return forward;
    const std::array<T, 3> v = traceVelocity(plane, c);
    const T backward = sample(first, plane, departure(c, v, -dt));
    const T mc = forward + T(0.5) * static_cast<T>(params_.strength) * (in_.field[at(plane, c)] - backward);

    const uint32_t fluidOrEmpty = physics::kFluid | physics::kEmpty;
    const int m = mode(plane) - 1;
    if (m >= 0 && (!(flag(c) & fluidOrEmpty) || !(flag(shifted(c, m, -1)) & fluidOrEmpty))) {
      ++diagnostics_.reverted;
      return forward;
    }
    Cell base{};
    for (int d = 0; d < 3; ++d) {
      const T position = static_cast<T>(c[d]) - v[d] * dt;
      base[d] = std::clamp(static_cast<int>(position), 0, grid_.size(d) - 2);
      const double nearest = std::clamp(std::round(static_cast<double>(position)), 1.0, grid_.size(d) - 2.0);
      noteMargin(static_cast<double>(position) - nearest);
    }
    T low = T(0), high = T(0);
    bool found = false;
    for (int corner = 0; corner < 8; ++corner) {
      const Cell cell{base[0] + (corner & 1), base[1] + ((corner >> 1) & 1), base[2] + (corner >> 2)};
      if (m < 0 && !(flag(cell) & fluidOrEmpty)) continue;
      const T value = in_.field[at(plane, cell)];
      low = found ? std::min(low, value) : value;
      high = found ? std::max(high, value) : value;
      found = true;
    }
    if (!found || mc < low || mc > high) {
      if (found) noteMargin(static_cast<double>(mc < low ? low - mc : mc - high));
      ++diagnostics_.reverted;
      return forward;
    }
    noteMargin(static_cast<double>(std::min(mc - low, high - mc)));
    ++diagnostics_.kept;
    return mc;
  }

  const AdvectionCase<T>& in_;
  ReferenceGrid grid_;
  physics::AdvectionParams params_;
  AdvectionDiagnostics& diagnostics_;
};

}  // namespace

template <typename T>
std::vector<T> referenceAdvect(const AdvectionCase<T>& input, const physics::AdvectionParams& params,
                               AdvectionDiagnostics* diagnostics) {
  AdvectionDiagnostics local;
  return Reference<T>(input, params, diagnostics ? *diagnostics : local).run();
}

template std::vector<float> referenceAdvect(const AdvectionCase<float>&, const physics::AdvectionParams&,
                                            AdvectionDiagnostics*);
template std::vector<double> referenceAdvect(const AdvectionCase<double>&, const physics::AdvectionParams&,
                                             AdvectionDiagnostics*);

}  // namespace smokesvd::testing

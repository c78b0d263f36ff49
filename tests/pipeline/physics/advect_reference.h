// Plain CPU reference of the advection operator (pipeline/physics/advection.h), written directly from
// mantaflow's rules, in float (to compare kernels with) or double (for finite differences).
#pragma once

#include <vector>

#include "pipeline/physics/advection.h"

namespace smokesvd::testing {

struct ReferenceGrid {
  int x = 0, y = 0, z = 0;
  int cells() const { return x * y * z; }
  int index(int i, int j, int k) const { return (k * y + j) * x + i; }
  int size(int axis) const { return axis == 0 ? x : axis == 1 ? y : z; }
};

template <typename T>
struct AdvectionCase {
  ReferenceGrid grid;
  std::vector<float> flags;  // [cells], mantaflow bits
  std::vector<T> field;      // [planes · cells]: one plane (scalar) or three (MAC)
  std::vector<T> velocity;   // [3 · cells], MAC
  std::vector<T> inflow;     // like field, or empty
  bool mac = false;
};

// What the reference saw on the way: the smallest distance of any decision quantity from its switch
// point (stencil cell boundaries, lookup clamps, the clamp's base index, the keep/revert bounds), and
// how many MacCormack corrections were kept and reverted.
struct AdvectionDiagnostics {
  double margin = 1e30;
  int kept = 0;
  int reverted = 0;
};

template <typename T>
std::vector<T> referenceAdvect(const AdvectionCase<T>& input, const physics::AdvectionParams& params,
                               AdvectionDiagnostics* diagnostics = nullptr);

}  // namespace smokesvd::testing

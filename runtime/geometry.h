// The vocabulary of grids and vectors every layer shares: one GridSize, one Vec3 (docs/conventions.md).
//
// A volume tensor is [D, H, W] = [z, y, x], x fastest, y up. GridSize names its sizes by axis, x = W,
// y = H, z = D, and is built one way only, with designated initialisers:
//     GridSize{.x = 64, .y = 112, .z = 64}
// A positional GridSize{a, b, c} does not compile (the first member below refuses a number), because the
// order of three sizes is what a reader cannot see at a call site. Vec3 is GLM's double vector; host-side
// vector and matrix maths is GLM's (glm::dot, glm::cross, glm::normalize, glm::dmat4, ...).
#pragma once

#include <cstdint>
#include <string>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "runtime/tensor.h"

namespace smokesvd {

using Vec3 = glm::dvec3;

// Only default-constructible: it makes GridSize{a, b, c} a compile error and costs no storage.
struct DesignatedInitialisersOnly {
  DesignatedInitialisersOnly() = default;
  bool operator==(const DesignatedInitialisersOnly&) const = default;
};

struct GridSize {
  [[no_unique_address]] DesignatedInitialisersOnly designatedOnly;
  int64_t x = 0, y = 0, z = 0;  // cells (voxels) along x (W), y (H, up), z (D)

  int64_t cells() const { return x * y * z; }
  Shape volume() const { return {z, y, x}; }     // [D, H, W]
  Shape vector() const { return {3, z, y, x}; }  // planar vector field [3, D, H, W]
  // The centre of the box [0, x] x [0, y] x [0, z] in grid coordinates.
  Vec3 centre() const { return {0.5 * static_cast<double>(x), 0.5 * static_cast<double>(y), 0.5 * static_cast<double>(z)}; }
  bool operator==(const GridSize&) const = default;
};

// The largest grid any command accepts, checked before anything is allocated for it: 1024 cells per side
// (a ray crosses at most ~1800 cells) and 2^28 cells in all (1 GiB per float field).
inline constexpr int64_t kMaxGridSide = 1024;
inline constexpr int64_t kMaxGridCells = int64_t{1} << 28;

// Throws Error("<what>: ...") unless every side is in [1, kMaxGridSide] and there are at most kMaxGridCells.
void checkGridSize(const GridSize& grid, const std::string& what);

}  // namespace smokesvd

// The simulation grid shared by the physics kernels (docs/conventions.md has the full statement).
//
// Volumes are float32 tensors [D, H, W] = [z, y, x], x fastest; element [k][j][i] is the cell with x index
// i, y index j, z index k, centred at (i+½, j+½, k+½) in cell units. Velocity is planar, [3, D, H, W]
// with component planes x, y, z:
//   - MAC (staggered, mantaflow's layout): plane 0 holds u_x at the lower x-face (i, j+½, k+½),
//     plane 1 u_y at (i+½, j, k+½), plane 2 u_z at (i+½, j+½, k); the upper face of the last cell
//     is not stored (it belongs to the wall).
//   - centred: every plane at the cell centre (what networks see).
// Velocity is in cells per time step. Cell flags are a float tensor [D, H, W] holding mantaflow's
// integer flag bits (1 fluid, 2 obstacle, 4 empty, ...).
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/context.h"
#include "runtime/geometry.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::physics {

enum CellFlag : uint32_t { kFluid = 1, kObstacle = 2, kEmpty = 4 };

// The grid of a volume [D, H, W] or of a planar vector field [3, D, H, W] (a leading batch of 1 is
// accepted for both). Throws Error naming `what` for any other shape or a side shorter than 3 cells.
GridSize volumeGrid(const Tensor& volume, const char* what);
GridSize vectorGrid(const Tensor& vectorField, const char* what);
// Throws Error naming `what` unless `tensor` is a volume [D, H, W] (or [1, D, H, W]) of `grid`.
void requireVolume(const Tensor& tensor, const GridSize& grid, const char* what);
void requireVector(const Tensor& tensor, const GridSize& grid, const char* what);

// A grid's cell flags with what the kernels derive from them once: per-cell masks packing a cell's own
// flags, its face neighbours' and its 2x2x2 block's (shaders/physics/advect_masks.comp), so that a
// MacCormack pass reads one texel instead of up to nine flags. Build it once per scene (flags change
// only when obstacles do); the masks are recorded into `stream` and valid for anything recorded after.
class FlagGrid {
 public:
  FlagGrid(Stream& stream, Tensor flags);

  const GridSize& size() const { return size_; }
  const Tensor& flags() const { return flags_; }
  const Tensor& masks() const { return masks_; }

 private:
  GridSize size_;
  Tensor flags_;
  Tensor masks_;
};

// Flags of a closed box: an outer layer `wallWidth` cells thick is obstacle, the rest fluid
// (mantaflow's initDomain(boundaryWidth = wallWidth - 1) followed by fillGrid()).
std::vector<float> closedBoxFlags(const GridSize& grid, int wallWidth = 1);
Tensor closedBoxFlagsTensor(Context& context, const GridSize& grid, int wallWidth = 1);

// Layout conversion of a vector field between the file layout [D, H, W, 3] (NumPy, mantaflow's
// .npz) and the planar layout [3, D, H, W] every kernel uses. Each is the other's inverse and adjoint.
void interleavedToPlanar(Stream& stream, const Tensor& interleaved, const Tensor& planar);
void planarToInterleaved(Stream& stream, const Tensor& planar, const Tensor& interleaved);

}  // namespace smokesvd::physics

// What the per-frame loop of a reconstruction carries from one frame to the next, on the device, and its
// checkpoint: the synthesised side views of the two previous frames and the side renders of their coarse
// densities (SvDiff's condition), the side view of frame 1 that SvDiff-init made with frame 0's, the
// refined images of all 16 view slots at the two previous frames (NvRef's history), and the physically
// consistent density and inflow of the previous frame (where the advection continues from).
#pragma once

#include <map>
#include <string>

#include "nets/io/npy.h"
#include "pipeline/preset.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::reconstruct {

struct FrameState {
  FrameState(Context& context, const Preset& preset);

  Tensor side1, side2;              // [1, 1, h, w]: synthesised side views of t-1 and t-2
  Tensor sideRender1, sideRender2;  // [1, 1, h, w]: 90-degree renders of their coarse densities
  Tensor pendingSide;               // [1, 1, h, w]: frame 1's side view, made at frame 0
  Tensor refined1, refined2;        // [16, 1, h, w]: refined views of t-1 and t-2
  Tensor density, inflow;           // [D, H, W]: the output density and inflow of t-1
  int framesDone = 0;               // frames of the clip already reconstructed

  // Moves t-1 to t-2 and the given frame's results to t-1 (recorded into `stream`).
  void advance(Stream& stream, const Tensor& side, const Tensor& sideRender, const Tensor& refined,
               const Tensor& density, const Tensor& inflow);

  std::map<std::string, io::NpyArray> toArrays() const;
  // Restores a checkpoint; Error naming `source` if an array is missing or of another shape.
  void fromArrays(const std::map<std::string, io::NpyArray>& arrays, const std::string& source);
};

}  // namespace smokesvd::reconstruct

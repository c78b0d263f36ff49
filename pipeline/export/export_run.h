// `smokesvd export`: a finished run folder (a reconstruction, a re-simulation or a simulation; pipeline/sim/
// saved_run.h) written for other tools (docs/applications.md):
//   --vdb        OUT/frame_NNNN.vdb: OpenVDB float grid "density" and vec3s grid "velocity" (Blender, Houdini)
//   --nerf       OUT/frame_NNNN/{transforms.json, transforms_train.json, transforms_test.json, images/}: the 16
//                orbit views of every frame with NeRF/nerfstudio cameras (3D Gaussian Splatting, NeRF tools)
//   --mantaflow  OUT/{density,velocity,inflow}_NNNN.npz, flags.npz: mantaflow's own .npz layout
// and OUT/export.json (what was written from what, the world placement, the conventions). The output folder
// must be absent or empty, or hold an export (then only with --overwrite); nothing else in it is touched, and
// a place that cannot be written is an error before any file is.
#pragma once

#include <filesystem>
#include <optional>


namespace smokesvd::exporters {

enum class Format { Vdb, Nerf, Mantaflow };

struct ExportOptions {
  std::filesystem::path source, out;
  Format format = Format::Vdb;
  std::optional<std::filesystem::path> calibration;  // overrides the one the run records
  bool zUp = false;                 // a z-up world (Blender)
  double cameraError = 0.25;        // --nerf: the largest reprojection error the pinhole cameras may make, pixels
  bool overwrite = false;
};

struct ExportResult {
  int frames = 0;
  std::filesystem::path index;      // export.json
};

ExportResult runExport(const ExportOptions& options);

// Whether this build can write OpenVDB files (CMake option SMOKESVD_OPENVDB).
bool openVdbAvailable();

}  // namespace smokesvd::exporters

// A run as OpenVDB files, one per frame, for Blender's volume import and Houdini: OUT/frame_NNNN.vdb holds
//   "density"   FloatGrid, fog volume, the run's density per voxel (the values smokesvd renders with its
//               absorption, recorded in the file's metadata);
//   "velocity"  Vec3SGrid, cell-centred (the MAC faces averaged: docs/conventions.md), in world units per second
//               (cells per step times the grid's world axes times the frame rate, one step a frame), world-space
//               vectors (vector type invariant).
// Voxel (i, j, k) of OpenVDB's index space is the cell of array element [k][j][i]; OpenVDB puts voxel centres at
// integer index coordinates, so index -> world is world_placement.h's grid -> world after a shift by half a cell.
// Only voxels whose value is not 0 are stored (active); every other voxel reads as the background 0.
// Built only with OpenVDB (CMake option SMOKESVD_OPENVDB); without it writeVdb is an Error saying so.
#pragma once

#include <filesystem>

#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "pipeline/export/world_placement.h"
#include "pipeline/sim/saved_run.h"

namespace smokesvd::exporters {

// Error unless this build has OpenVDB (export_run.h: openVdbAvailable), naming what to install.
void requireOpenVdb();

// OpenVDB's index -> world matrix (column vectors, as GLM) of a placement.
glm::dmat4 vdbIndexToWorld(const WorldPlacement& placement);

// Cell-centred velocity [D, H, W] x 3 (interleaved) in world units per second from a planar MAC velocity in
// cells per step.
std::vector<float> worldVelocity(const std::vector<float>& mac, const GridSize& grid, const WorldPlacement& placement,
                                 double frameRate);

nlohmann::json writeVdb(const sim::SavedRun& run, const WorldPlacement& placement, const std::filesystem::path& out);

}  // namespace smokesvd::exporters

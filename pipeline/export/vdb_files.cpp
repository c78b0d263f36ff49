#include "pipeline/export/vdb_files.h"

#include <glm/gtc/matrix_transform.hpp>

#include "pipeline/export/export_run.h"
#include "pipeline/sim/outputs.h"
#include "runtime/error.h"

#if SMOKESVD_WITH_OPENVDB
#include <openvdb/openvdb.h>
#endif

namespace smokesvd::exporters {
namespace fs = std::filesystem;

glm::dmat4 vdbIndexToWorld(const WorldPlacement& placement) {
  return placement.gridToWorld * glm::translate(glm::dmat4(1.0), glm::dvec3(0.5));
}

std::vector<float> worldVelocity(const std::vector<float>& mac, const GridSize& g, const WorldPlacement& placement,
                                 double frameRate) {
  const std::size_t cells = static_cast<std::size_t>(g.cells());
  const int64_t sizes[3] = {g.x, g.y, g.z}, strides[3] = {1, g.x, g.x * g.y};
  const glm::dmat3 L = placement.linear();
  std::vector<float> out(3 * cells);
  for (int64_t k = 0; k < g.z; ++k)
    for (int64_t j = 0; j < g.y; ++j)
      for (int64_t i = 0; i < g.x; ++i) {
        const int64_t c = (k * g.y + j) * g.x + i, index[3] = {i, j, k};
        glm::dvec3 centred;
        for (int a = 0; a < 3; ++a) {
          const std::size_t plane = static_cast<std::size_t>(a) * cells;
          const double lower = mac[plane + static_cast<std::size_t>(c)];
          const double upper = index[a] + 1 < sizes[a] ? mac[plane + static_cast<std::size_t>(c + strides[a])] : 0.0;
          centred[a] = 0.5 * (lower + upper);
        }
        const glm::dvec3 world = L * centred * frameRate;
        for (int a = 0; a < 3; ++a) out[3 * static_cast<std::size_t>(c) + static_cast<std::size_t>(a)] = static_cast<float>(world[a]);
      }
  return out;
}

void requireOpenVdb() {
  if (!openVdbAvailable())
    throw Error("--vdb: this smokesvd was built without OpenVDB (install libopenvdb-dev and libboost-iostreams-dev, "
                "then configure and build again; docs/dependencies.md)");
}

#if SMOKESVD_WITH_OPENVDB

bool openVdbAvailable() { return true; }

nlohmann::json writeVdb(const sim::SavedRun& run, const WorldPlacement& placement, const fs::path& out) {
  openvdb::initialize();
  const GridSize g = run.grid();
  const glm::dmat4 m = vdbIndexToWorld(placement);
  // OpenVDB multiplies row vectors (translation in the last row): its matrix is GLM's storage read as rows.
  openvdb::math::Mat4d rowVector;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) rowVector(r, c) = m[r][c];
  const openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(rowVector);
  const std::string units = "density per voxel as smokesvd renders it with absorption " +
                            std::to_string(run.scene.render.absorption) + " per voxel; velocity in world units per second";
  for (int t = 0; t < run.frames; ++t) {
    const std::vector<float> density = run.density(t);
    const std::vector<float> velocity = worldVelocity(run.velocity(t), g, placement, run.frameRate);
    openvdb::FloatGrid::Ptr densityGrid = openvdb::FloatGrid::create(0.0f);
    openvdb::Vec3SGrid::Ptr velocityGrid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    {
      openvdb::FloatGrid::Accessor d = densityGrid->getAccessor();
      openvdb::Vec3SGrid::Accessor v = velocityGrid->getAccessor();
      for (int64_t k = 0; k < g.z; ++k)
        for (int64_t j = 0; j < g.y; ++j)
          for (int64_t i = 0; i < g.x; ++i) {
            const std::size_t c = static_cast<std::size_t>((k * g.y + j) * g.x + i);
            const openvdb::Coord ijk(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
            if (density[c] != 0.0f) d.setValue(ijk, density[c]);
            const openvdb::Vec3s u(velocity[3 * c], velocity[3 * c + 1], velocity[3 * c + 2]);
            if (u != openvdb::Vec3s(0.0f)) v.setValue(ijk, u);
          }
    }
    densityGrid->setName("density");
    densityGrid->setGridClass(openvdb::GRID_FOG_VOLUME);
    densityGrid->setTransform(transform);
    velocityGrid->setName("velocity");
    velocityGrid->setVectorType(openvdb::VEC_INVARIANT);
    velocityGrid->setTransform(transform);
    openvdb::MetaMap meta;
    meta.insertMeta("smokesvd_source", openvdb::StringMetadata(fs::absolute(run.root).string()));
    meta.insertMeta("smokesvd_frame", openvdb::Int32Metadata(t));
    meta.insertMeta("smokesvd_units", openvdb::StringMetadata(units));
    meta.insertMeta("smokesvd_absorption_per_voxel", openvdb::DoubleMetadata(run.scene.render.absorption));
    meta.insertMeta("smokesvd_frame_rate", openvdb::DoubleMetadata(run.frameRate));
    const fs::path path = out / ("frame_" + sim::frameName(t) + ".vdb");
    fs::path temporary = path;
    temporary += ".tmp";
    try {
      openvdb::io::File file(temporary.string());
      file.write({densityGrid, velocityGrid}, meta);
      file.close();
    } catch (const openvdb::Exception& e) {
      fs::remove(temporary);
      throw Error(temporary.string() + ": cannot write the OpenVDB file (" + e.what() + ")");
    }
    fs::rename(temporary, path);
  }
  return {{"files", "frame_NNNN.vdb: FloatGrid density (fog volume), Vec3SGrid velocity (cell-centred, world units per second)"},
          {"index_to_world", "OpenVDB voxel (i, j, k) = array element [k][j][i], centred at grid point (i + 1/2, j + 1/2, k + 1/2)"},
          {"frame_rate", run.frameRate},
          {"absorption_per_voxel", run.scene.render.absorption}};
}

#else

bool openVdbAvailable() { return false; }

nlohmann::json writeVdb(const sim::SavedRun&, const WorldPlacement&, const fs::path&) {
  requireOpenVdb();
  return {};
}

#endif

}  // namespace smokesvd::exporters

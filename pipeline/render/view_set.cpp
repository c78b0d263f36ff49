#include "pipeline/render/view_set.h"

#include <algorithm>
#include <cmath>

#include "runtime/error.h"

namespace smokesvd::render {
namespace {

constexpr int kFloatsPerView = 36;

void put(std::vector<float>& out, const Vec3& v, double w) {
  for (double x : {v.x, v.y, v.z, w}) out.push_back(static_cast<float>(x));
}

// Whether every ray of `c` runs along a row of voxel centres and its projection maps each voxel row onto a
// pixel row (ViewSet::raysInVoxelRows), as the table's floats give them to the kernels: ray_in_voxel_row and
// projection_in_pixel_rows (shaders/render/sampling.glsl, camera.glsl) hold for every pixel and voxel.
bool raysInVoxelRows(const Camera& c) {
  const auto single = [](double v) { return static_cast<double>(static_cast<float>(v)); };
  const auto integral = [&](double v) { return std::floor(single(v)) == single(v); };
  const Vec3 zero{0.0, 0.0, 0.0};
  const glm::dmat4x3& m = c.projection;  // m[column][row]
  const bool rays = !c.perspective && single(c.originPerU.y) == 0.0 && single(c.originPerV.x) == 0.0 &&
                    single(c.originPerV.y) == -1.0 && single(c.originPerV.z) == 0.0 && single(c.direction.y) == 0.0 &&
                    c.directionPerU == zero && c.directionPerV == zero && integral(c.origin.y);
  const bool projection = m[0][2] == 0.0 && m[1][2] == 0.0 && m[2][2] == 0.0 && single(m[3][2]) == 1.0 &&
                          single(m[1][0]) == 0.0 && single(m[0][1]) == 0.0 && single(m[1][1]) == -1.0 &&
                          single(m[2][1]) == 0.0 && integral(m[3][1]);
  return rays && projection;
}

bool allRaysInVoxelRows(std::span<const Camera> cameras) {
  return std::all_of(cameras.begin(), cameras.end(), [](const Camera& c) { return raysInVoxelRows(c); });
}

std::vector<float> cameraTable(const ViewSet& set, std::span<const Camera> cameras) {
  std::vector<float> table;
  table.reserve(cameras.size() * kFloatsPerView);
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const Camera& c = cameras[i];
    if (c.width != set.width || c.height != set.height)
      throw Error("render views: camera " + std::to_string(i) + " renders " + std::to_string(c.width) + "x" +
                  std::to_string(c.height) + " pixels but camera 0 renders " + std::to_string(set.width) + "x" +
                  std::to_string(set.height) + "; one dispatch needs one image size");
    put(table, c.origin, c.perspective ? 1.0 : 0.0);
    put(table, c.originPerU, 0);
    put(table, c.originPerV, 0);
    put(table, c.direction, 0);
    put(table, c.directionPerU, 0);
    put(table, c.directionPerV, 0);
    for (int row = 0; row < 3; ++row)
      for (int column = 0; column < 4; ++column) table.push_back(static_cast<float>(c.projection[column][row]));
  }
  return table;
}

}  // namespace

ViewSet uploadViews(Context& context, std::span<const Camera> cameras) {
  if (cameras.empty()) throw Error("render views: no cameras given");
  ViewSet set;
  set.views = static_cast<int>(cameras.size());
  set.width = cameras[0].width;
  set.height = cameras[0].height;
  set.table = Tensor::fromHost(context, {set.views, kFloatsPerView}, cameraTable(set, cameras));
  set.raysInVoxelRows = allRaysInVoxelRows(cameras);
  return set;
}

void rewriteViews(const ViewSet& views, std::span<const Camera> cameras) {
  if (static_cast<int>(cameras.size()) != views.views)
    throw Error("render views: " + std::to_string(cameras.size()) + " cameras for a table of " +
                std::to_string(views.views) + " views");
  if (allRaysInVoxelRows(cameras) != views.raysInVoxelRows)
    throw Error(std::string("render views: the new cameras' rays ") + (views.raysInVoxelRows ? "do not run" : "run") +
                " along rows of voxel centres as the uploaded ones' " + (views.raysInVoxelRows ? "do" : "do not") +
                " (recordings choose their kernels by it); upload a view set of their own");
  views.table.upload(cameraTable(views, cameras));
}

GridSize volumeGrid(const Tensor& volume, const char* what) {
  const Shape& shape = volume.shape();
  bool ok = shape.size() >= 3;
  for (std::size_t i = 0; ok && i + 3 < shape.size(); ++i) ok = shape[i] == 1;
  if (!ok || volume.numel() == 0)
    throw Error(std::string(what) + ": expected a volume [D, H, W] (leading dimensions of size 1 allowed), got " +
                toString(shape));
  return {.x = shape[shape.size() - 1], .y = shape[shape.size() - 2], .z = shape[shape.size() - 3]};
}

}  // namespace smokesvd::render

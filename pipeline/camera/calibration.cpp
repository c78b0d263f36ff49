#include "pipeline/camera/calibration.h"

#include <cmath>
#include <fstream>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "nets/io/file_io.h"
#include "runtime/error.h"

namespace smokesvd {
namespace {

using nlohmann::json;

// The inverse of an affine 4x4 (last row 0 0 0 1), or nothing if its linear part is singular.
std::optional<glm::dmat4> inverseAffine(const glm::dmat4& m) {
  if (std::abs(glm::determinant(glm::dmat3(m))) < 1e-300) return std::nullopt;
  return glm::inverse(m);
}

class FieldReader {
 public:
  explicit FieldReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& expected) const {
    throw Error(file_ + ": field '" + field + "': expected " + expected);
  }

  const json& member(const json& object, const std::string& key, const std::string& field) const {
    if (!object.is_object() || !object.contains(key)) fail(field, "to be present");
    return object.at(key);
  }

  double number(const json& value, const std::string& field) const {
    if (!value.is_number()) fail(field, "a number");
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(field, "a finite number");
    return x;
  }

  std::vector<double> numbers(const json& value, const std::string& field, std::size_t count) const {
    const std::string expected = "an array of " + std::to_string(count) + " numbers";
    if (!value.is_array() || value.size() != count) fail(field, expected);
    std::vector<double> result;
    for (std::size_t i = 0; i < count; ++i) result.push_back(number(value[i], field + "[" + std::to_string(i) + "]"));
    return result;
  }

  // The file writes a matrix as its rows; GLM indexes m[column][row].
  glm::dmat4 matrix(const json& value, const std::string& field) const {
    if (!value.is_array() || value.size() != 4) fail(field, "a 4x4 matrix (4 rows of 4 numbers)");
    glm::dmat4 m{0.0};
    for (int row = 0; row < 4; ++row) {
      const std::string name = field + "[" + std::to_string(row) + "]";
      const std::vector<double> r = numbers(value[static_cast<std::size_t>(row)], name, 4);
      for (int col = 0; col < 4; ++col) m[col][row] = r[static_cast<std::size_t>(col)];
    }
    if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1)
      fail(field, "an affine matrix (last row 0 0 0 1)");
    if (!inverseAffine(m)) fail(field, "an invertible matrix");
    return m;
  }

 private:
  std::string file_;
};

CalibratedView readView(const FieldReader& reader, const json& entry, const std::string& field) {
  CalibratedView view;
  const json& name = reader.member(entry, "file_name", field + ".file_name");
  if (!name.is_string()) reader.fail(field + ".file_name", "a string");
  view.fileName = name.get<std::string>();
  view.cameraAngleX = reader.number(reader.member(entry, "camera_angle_x", field + ".camera_angle_x"),
                                    field + ".camera_angle_x");
  if (view.cameraAngleX <= 0 || view.cameraAngleX >= 3.1)
    reader.fail(field + ".camera_angle_x", "a field of view in radians in (0, 3.1)");
  const std::vector<double> hw = reader.numbers(reader.member(entry, "camera_hw", field + ".camera_hw"),
                                                field + ".camera_hw", 2);
  if (hw[0] < 1 || hw[1] < 1 || hw[0] > 65536 || hw[1] > 65536 || hw[0] != std::floor(hw[0]) ||
      hw[1] != std::floor(hw[1]))
    reader.fail(field + ".camera_hw", "[height, width] as whole numbers from 1 to 65536");
  view.height = static_cast<int>(hw[0]);
  view.width = static_cast<int>(hw[1]);
  view.cameraToWorld = reader.matrix(reader.member(entry, "transform_matrix", field + ".transform_matrix"),
                                     field + ".transform_matrix");
  if (entry.contains("frame_rate")) {
    view.frameRate = reader.number(entry["frame_rate"], field + ".frame_rate");
    if (view.frameRate < 0 || view.frameRate > 1e4) reader.fail(field + ".frame_rate", "frames per second from 0 to 10000");
  }
  if (entry.contains("frame_num")) {
    const double count = reader.number(entry["frame_num"], field + ".frame_num");
    if (count < 0 || count > 1e9 || count != std::floor(count))
      reader.fail(field + ".frame_num", "a whole number of frames from 0 to 1e9");
    view.frameCount = static_cast<int>(count);
  }
  return view;
}

}  // namespace

glm::dmat4 VolumeBox::gridToWorld(const GridSize& grid) const {
  // Grid (x, y, z) -> box coordinates in tensor order (scale_z z / D, scale_y y / H, scale_x x / W).
  const glm::dmat4 boxFromGrid = glm::transpose(glm::dmat4(0, 0, scale.z / static_cast<double>(grid.z), 0,  // rows
                                                           0, scale.y / static_cast<double>(grid.y), 0, 0,
                                                           scale.x / static_cast<double>(grid.x), 0, 0, 0,
                                                           0, 0, 0, 1));
  return voxelMatrix * boxFromGrid;
}

const CalibratedView& Calibration::view(const std::string& fileName) const {
  std::string names;
  for (const CalibratedView& v : views) {
    if (v.fileName == fileName) return v;
    names += (names.empty() ? "" : ", ") + v.fileName;
  }
  throw Error("calibration has no view '" + fileName + "'; it has: " + names);
}

Calibration readCalibration(const std::filesystem::path& path) {
  json root;
  try {
    root = json::parse(io::readTextFile(path));
  } catch (const json::exception& e) {
    throw Error(path.string() + ": not valid JSON (" + e.what() + ")");
  }
  const FieldReader reader(path.string());
  Calibration calibration;
  for (const char* list : {"train_videos", "test_videos"}) {
    if (!root.contains(list)) continue;
    const json& entries = root[list];
    if (!entries.is_array()) reader.fail(list, "an array of views");
    for (std::size_t i = 0; i < entries.size(); ++i)
      calibration.views.push_back(readView(reader, entries[i], std::string(list) + "[" + std::to_string(i) + "]"));
  }
  if (calibration.views.empty()) reader.fail("train_videos", "at least one view in train_videos or test_videos");
  calibration.box.voxelMatrix = reader.matrix(reader.member(root, "voxel_matrix", "voxel_matrix"), "voxel_matrix");
  const std::vector<double> scale = reader.numbers(reader.member(root, "voxel_scale", "voxel_scale"), "voxel_scale", 3);
  for (double s : scale)
    if (s <= 0) reader.fail("voxel_scale", "three positive box sizes [x, y, z]");
  calibration.box.scale = {scale[0], scale[1], scale[2]};
  return calibration;
}

Camera calibratedCamera(const CalibratedView& view, const VolumeBox& box, const GridSize& grid, int width) {
  if (width < 0) throw Error("calibrated camera '" + view.fileName + "': negative image width");
  const int w = width == 0 ? view.width : width;
  const int h = width == 0 ? view.height
                           : std::max(1, static_cast<int>(std::lround(static_cast<double>(w) * view.height / view.width)));
  const double focal = 0.5 * w / std::tan(0.5 * view.cameraAngleX);
  const glm::dmat4 gridToWorld = box.gridToWorld(grid);
  const std::optional<glm::dmat4> worldToGrid = inverseAffine(gridToWorld);
  if (!worldToGrid) throw Error("calibrated camera: the volume box is degenerate");
  const std::optional<glm::dmat4> worldToCamera = inverseAffine(view.cameraToWorld);
  if (!worldToCamera) throw Error("calibrated camera '" + view.fileName + "': transform_matrix is singular");
  const glm::dmat4 cameraToGrid = *worldToGrid * view.cameraToWorld;
  auto point = [&](const Vec3& p) { return Vec3(cameraToGrid * glm::dvec4(p, 1.0)); };
  auto direction = [&](const Vec3& d) { return Vec3(cameraToGrid * glm::dvec4(d, 0.0)); };

  Camera camera;
  camera.width = w;
  camera.height = h;
  camera.perspective = true;
  camera.origin = point({0, 0, 0});
  camera.direction = direction({-0.5 * w / focal, 0.5 * h / focal, -1.0});
  camera.directionPerU = direction({1.0 / focal, 0, 0});
  camera.directionPerV = direction({0, -1.0 / focal, 0});
  // (a, b, c) = K (camera-space point), K = [[f, 0, -w/2], [0, -f, -h/2], [0, 0, -1]]: u = a / c, v = b / c.
  const glm::dmat4 intrinsics = glm::transpose(glm::dmat4(focal, 0, -0.5 * w, 0,  // rows
                                                          0, -focal, -0.5 * h, 0,
                                                          0, 0, -1, 0,
                                                          0, 0, 0, 1));
  camera.projection = glm::dmat4x3(intrinsics * *worldToCamera * gridToWorld);
  return camera;
}

std::array<Vec3, 8> gridCorners(const GridSize& grid) {
  std::array<Vec3, 8> corners{};
  for (std::size_t i = 0; i < 8; ++i)
    corners[i] = {(i & 1) ? static_cast<double>(grid.x) : 0.0, (i & 2) ? static_cast<double>(grid.y) : 0.0,
                  (i & 4) ? static_cast<double>(grid.z) : 0.0};
  return corners;
}

}  // namespace smokesvd

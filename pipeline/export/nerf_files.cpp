#include "pipeline/export/nerf_files.h"

#include <cmath>

#include "nets/io/json_file.h"
#include "pipeline/export/nerf_cameras.h"
#include "pipeline/media/image.h"
#include "pipeline/sim/outputs.h"
#include "runtime/error.h"

namespace smokesvd::exporters {
namespace fs = std::filesystem;
namespace {

std::string viewName(int view) {
  char name[16];
  std::snprintf(name, sizeof name, "view_%02d", view);
  return name;
}

nlohmann::json rows(const glm::dmat4& m) {
  nlohmann::json out = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) out.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
  return out;
}

}  // namespace

nlohmann::json writeNerf(const sim::SavedRun& run, const WorldPlacement& placement, double maxErrorPixels, const fs::path& out) {
  const sim::RenderSpec& spec = run.scene.render;
  const std::vector<double> angles = orbitAngles(spec.views);
  const std::vector<Camera> views = orbitCameras(angles, run.grid(), spec.width, spec.height);
  const PinholeApproximation pinholes = pinholeCameras(views, run.grid(), placement, maxErrorPixels);
  const PinholeCamera& first = pinholes.cameras.front();
  for (int t = 0; t < run.frames; ++t)
    for (std::size_t v = 0; v < views.size(); ++v)
      if (!fs::exists(run.root / "renders" / viewName(static_cast<int>(v)) / (sim::frameName(t) + ".png")))
        throw Error(run.root.string() + ": renders/" + viewName(static_cast<int>(v)) + "/" + sim::frameName(t) +
                    ".png is missing; --nerf exports the run's orbit views");
  nlohmann::json orthographic = nlohmann::json::array();
  for (std::size_t v = 0; v < views.size(); ++v)
    orthographic.push_back({{"file_path", "images/" + viewName(static_cast<int>(v)) + ".png"}, {"orbit_angle_degrees", angles[v]}});
  const nlohmann::json note{
      {"projection", "the images are orthographic orbit views about the box's vertical axis; these pinhole cameras "
                     "reproduce them to within max_reprojection_error_pixels over the box"},
      {"camera_distance", pinholes.distance},
      {"max_reprojection_error_pixels", pinholes.maxErrorPixels},
      {"world", placement.describe()},
      {"views", orthographic}};
  for (int t = 0; t < run.frames; ++t) {
    const fs::path folder = out / ("frame_" + sim::frameName(t));
    fs::create_directories(folder / "images");
    nlohmann::json frames = nlohmann::json::array(), synthetic = nlohmann::json::array();
    for (std::size_t v = 0; v < views.size(); ++v) {
      const std::string name = viewName(static_cast<int>(v));
      const media::Image gray = media::readPng(run.root / "renders" / name / (sim::frameName(t) + ".png"));
      media::writePng(folder / "images" / (name + ".png"), media::toRgb(gray), 8);
      const nlohmann::json pose = rows(pinholes.cameras[v].cameraToWorld);
      frames.push_back({{"file_path", "images/" + name + ".png"}, {"transform_matrix", pose}});
      synthetic.push_back({{"file_path", "./images/" + name}, {"transform_matrix", pose}});
    }
    nlohmann::json transforms{{"camera_model", "OPENCV"}, {"fl_x", first.fx}, {"fl_y", first.fy}, {"cx", first.cx},
                              {"cy", first.cy},           {"w", first.width}, {"h", first.height}, {"k1", 0},
                              {"k2", 0},                  {"p1", 0},          {"p2", 0},           {"frames", frames},
                              {"smokesvd", note}};
    transforms["smokesvd"]["frame"] = t;
    io::writeJsonFile(folder / "transforms.json", transforms);
    if (pinholes.squarePixels) {
      const double angleX = 2 * std::atan(0.5 * first.width / first.fx);
      io::writeJsonFile(folder / "transforms_train.json", {{"camera_angle_x", angleX}, {"frames", synthetic}});
      io::writeJsonFile(folder / "transforms_test.json", {{"camera_angle_x", angleX}, {"frames", nlohmann::json::array()}});
    }
  }
  return {{"folders", "frame_NNNN/ with images/view_VV.png (8-bit RGB), transforms.json (nerfstudio)" +
                          std::string(pinholes.squarePixels ? ", transforms_train.json and transforms_test.json (NeRF-synthetic)"
                                                            : "; no NeRF-synthetic files: the pixels are not square")},
          {"views", views.size()},
          {"camera_distance", pinholes.distance},
          {"max_reprojection_error_pixels", pinholes.maxErrorPixels},
          {"square_pixels", pinholes.squarePixels}};
}

}  // namespace smokesvd::exporters

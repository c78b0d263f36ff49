// The front views of calibrated footage (pipeline/reconstruct/front_views.h): the perspective footage
// rectified onto the box's mid-plane is the orthographic front view of smoke in that plane, and the crops
// as the camera saw them are kept, with their camera, beside the rectified views.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "pipeline/camera/calibration.h"
#include "pipeline/reconstruct/front_views.h"
#include "tests/pipeline/render/scenes.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

// A smooth sheet of smoke in the plane z = D/2: two blobs, in grid coordinates (x, y).
double sheet(const GridSize& grid, double x, double y) {
  const double w = static_cast<double>(grid.x), h = static_cast<double>(grid.y);
  auto blob = [](double dx, double dy, double r) { return std::exp(-(dx * dx + dy * dy) / (2 * r * r)); };
  return 0.8 * blob(x - 0.4 * w, y - 0.3 * h, 0.12 * w) + 0.5 * blob(x - 0.65 * w, y - 0.7 * h, 0.08 * w);
}

// What `camera` films of the sheet: each pixel the sheet's value where its central ray crosses the plane,
// averaged over 4 x 4 rays.
media::Image filmSheet(const Camera& camera, const GridSize& g) {
  media::Image image = media::Image::gray(camera.width, camera.height);
  for (int r = 0; r < camera.height; ++r)
    for (int c = 0; c < camera.width; ++c) {
      double sum = 0;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          const Ray ray = camera.ray(c + (i + 0.5) / 4, r + (j + 0.5) / 4);
          const double t = (0.5 * static_cast<double>(g.z) - ray.origin.z) / ray.direction.z;
          const Vec3 p = ray.origin + t * ray.direction;
          sum += sheet(g, p.x, p.y);
        }
      image.values[static_cast<std::size_t>(r * camera.width + c)] = static_cast<float>(sum / 16);
    }
  return image;
}

double maxError(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(static_cast<double>(a[i]) - b[i]));
  return worst;
}

TEST(FrontViewsTest, TheRectifiedPerspectiveViewOfTheMidPlaneIsItsOrthographicView) {
  const Preset& p = preset("small");
  const GridSize& g = p.grid;
  // As ScalarFlow's front camera: about 2.5 box widths from the centre, 1.3 px of footage per front pixel and more.
  const Vec3 centre = g.centre();
  const Camera source = lookAtCamera(g, {centre.x, centre.y, -2.5 * static_cast<double>(g.x)}, 180, 320, 0.9);
  const media::Image footage = filmSheet(source, g);
  const Camera front = orbitCamera(0, g, p.imageWidth, p.imageHeight);
  std::vector<float> truth(static_cast<std::size_t>(p.imageWidth * p.imageHeight));
  for (int r = 0; r < p.imageHeight; ++r)
    for (int c = 0; c < p.imageWidth; ++c) {
      const Ray ray = front.ray(c + 0.5, r + 0.5);
      truth[static_cast<std::size_t>(r * p.imageWidth + c)] = static_cast<float>(sheet(g, ray.origin.x, ray.origin.y));
    }

  const std::vector<float> rectified = reconstruct::rectifyToMidPlane(footage, source, front, g);
  const std::vector<float> crop = reconstruct::resampleRegion(
      footage, reconstruct::calibratedRegion(source, g, static_cast<double>(p.imageWidth) / p.imageHeight), p.imageWidth,
      p.imageHeight);
  const double rectifiedError = maxError(rectified, truth), cropError = maxError(crop, truth);
  EXPECT_LT(rectifiedError, 0.02);
  // The crop frames the whole box, whose near face looks larger than its mid-plane: the sheet is shrunk in it.
  EXPECT_GT(cropError, 10 * rectifiedError);
}

TEST(FrontViewsTest, CalibratedFootageKeepsTheCamerasCropsBesideTheRectifiedViews) {
  const Preset& p = preset("tiny");
  io::TemporaryFolder folder("front-views");
  // A box of 0.5 x 0.875 x 0.5 m, grid +z along world -z, filmed by a camera 1.2 m in front of it.
  std::ofstream(folder / "info.json") << R"({
    "train_videos": [{"file_name": "stack.npy", "camera_angle_x": 0.5, "camera_hw": [140, 80],
                      "transform_matrix": [[1, 0, 0, 0.25], [0, 1, 0, 0.4375], [0, 0, 1, 1.2], [0, 0, 0, 1]]}],
    "voxel_matrix": [[0, 0, 1, 0], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]],
    "voxel_scale": [0.5, 0.875, 0.5]})";
  std::vector<float> values(2 * 140 * 80);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<float>((i * 7919) % 101) / 100.0f;
  io::writeNpy(folder / "stack.npy", io::NpyArray::fromFloats({2, 140, 80}, values));

  reconstruct::InputOptions o;
  o.input = folder / "stack.npy";
  o.framing = reconstruct::Framing::Calibrated;
  o.calibration = folder / "info.json";
  o.intensity = "none";
  const reconstruct::FrontViews views = reconstruct::readFrontViews(o, p);
  ASSERT_TRUE(views.camera.has_value());
  EXPECT_NEAR(orbitAngleOf(*views.camera), 0.0, 1e-6);
  EXPECT_TRUE(views.rectified);
  ASSERT_EQ(views.frames.size(), 2u);
  ASSERT_EQ(views.inputFrames.size(), 2u);
  media::Image first = media::Image::gray(80, 140);
  std::copy(values.begin(), values.begin() + 140 * 80, first.values.begin());
  EXPECT_EQ(views.inputFrames[0], reconstruct::resampleRegion(first, views.region, p.imageWidth, p.imageHeight));
  EXPECT_EQ(views.frames[0], reconstruct::rectifyToMidPlane(first, *views.camera,
                                                             orbitCamera(0, p.grid, p.imageWidth, p.imageHeight), p.grid));
  EXPECT_NE(views.frames[0], views.inputFrames[0]);
  // The input camera is the calibrated camera over the region, at the preset's size.
  ASSERT_TRUE(views.inputCamera.perspective);
  EXPECT_EQ(views.inputCamera.width, p.imageWidth);
  EXPECT_EQ(views.inputCamera.height, p.imageHeight);
  for (const Vec3& corner : gridCorners(p.grid)) {
    const auto full = views.camera->project(corner), window = views.inputCamera.project(corner);
    ASSERT_TRUE(full && window);
    EXPECT_NEAR((*window)[0], ((*full)[0] - views.region.x0) * p.imageWidth / views.region.width, 1e-6);
    EXPECT_NEAR((*window)[1], ((*full)[1] - views.region.y0) * p.imageHeight / views.region.height, 1e-6);
  }

  o.orthographic = true;
  const reconstruct::FrontViews crops = reconstruct::readFrontViews(o, p);
  EXPECT_FALSE(crops.rectified);
  EXPECT_EQ(crops.frames, crops.inputFrames);
  EXPECT_EQ(crops.inputFrames, views.inputFrames);
  EXPECT_FALSE(crops.inputCamera.perspective);
  EXPECT_NE(crops.describe()["front_views"], views.describe()["front_views"]);
}

}  // namespace
}  // namespace smokesvd::testing

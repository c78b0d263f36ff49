#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "nets/io/temporary_folder.h"
#include "pipeline/camera/calibration.h"
#include "pipeline/media/video.h"
#include "pipeline/render/calibration_check.h"
#include "runtime/error.h"
#include "tests/harness/test_data.h"
#include "tests/pipeline/render/scenes.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

void expectNear(const Vec3& a, const Vec3& b, double tolerance = 1e-9) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tolerance) << "component " << i;
}

TEST(CameraTest, OrbitAnglesAreEvenOnHalfATurn) {
  const std::vector<double> angles = orbitAngles(16);
  ASSERT_EQ(angles.size(), 16u);
  for (int i = 0; i < 16; ++i) EXPECT_DOUBLE_EQ(angles[static_cast<std::size_t>(i)], 11.25 * i);
  EXPECT_THROW(orbitAngles(0), Error);
}

TEST(CameraTest, FrontViewLooksAlongPlusZWithColumnsAlongX) {
  const GridSize grid{.x = 6, .y = 7, .z = 5};
  const Camera front = orbitCamera(0, grid, 6, 7);
  const Ray ray = front.ray(2.5, 1.5);  // column 2, row 1
  expectNear(ray.direction, {0, 0, 1});
  EXPECT_NEAR(ray.origin[0], 2.5, 1e-12);
  EXPECT_NEAR(ray.origin[1], 7 - 1.5, 1e-12);
  EXPECT_LT(ray.origin[2], 0.0);
  const auto uv = front.project({2.5, 5.5, 3.0});
  ASSERT_TRUE(uv);
  EXPECT_NEAR((*uv)[0], 2.5, 1e-12);
  EXPECT_NEAR((*uv)[1], 1.5, 1e-12);
}

TEST(CameraTest, SideViewLooksAlongMinusXWithColumnsAlongZ) {
  const GridSize grid{.x = 6, .y = 4, .z = 6};
  const Camera side = orbitCamera(90, grid, 6, 4);
  expectNear(side.forward(), {-1, 0, 0}, 1e-12);
  const auto a = side.project({3, 2, 1.5}), b = side.project({3, 2, 4.5});
  ASSERT_TRUE(a && b);
  EXPECT_NEAR((*a)[0], 1.5, 1e-9);
  EXPECT_NEAR((*b)[0], 4.5, 1e-9);
}

TEST(CameraTest, OrbitAngleOfAnOrbitCameraIsItsAngle) {
  const GridSize grid{.x = 6, .y = 7, .z = 5};
  for (double angle : {0.0, 11.25, 45.0, 90.0, 135.0, 168.75, -30.0})
    EXPECT_NEAR(orbitAngleOf(orbitCamera(angle, grid, 6, 7)), angle, 1e-9);
}

TEST(CameraTest, RaysAndProjectionAgreeForEveryCameraKind) {
  const GridSize grid{.x = 6, .y = 7, .z = 5};
  for (const Camera& camera : mixedCameras(grid, 9, 8)) {
    for (double u : {0.5, 3.25, 8.5})
      for (double v : {0.5, 5.75}) {
        const Ray ray = camera.ray(u, v);
        EXPECT_NEAR(glm::length(ray.direction), 1.0, 1e-12);
        const auto uv = camera.project(ray.origin + 7.0 * ray.direction);
        ASSERT_TRUE(uv);
        EXPECT_NEAR((*uv)[0], u, 1e-9);
        EXPECT_NEAR((*uv)[1], v, 1e-9);
      }
  }
}

TEST(CameraTest, AWindowCameraSeesTheWindowOfItsCamera) {
  CalibratedView view;
  view.fileName = "v.mp4";
  view.cameraAngleX = 0.6;
  view.width = 300;
  view.height = 200;
  view.cameraToWorld = glm::dmat4(1.0);
  view.cameraToWorld[3] = glm::dvec4(0.3, 0.4, 3.0, 1.0);
  VolumeBox box;
  box.scale = {1, 1, 1};
  const GridSize grid{.x = 8, .y = 10, .z = 6};
  for (const Camera& camera : {orbitCamera(30, grid, 16, 20), calibratedCamera(view, box, grid)}) {
    const double x0 = -3.5, y0 = 12.25, w = 41.0, h = 37.0;
    const Camera window = windowCamera(camera, x0, y0, w, h, 9, 13);
    EXPECT_EQ(window.width, 9);
    EXPECT_EQ(window.height, 13);
    EXPECT_EQ(window.perspective, camera.perspective);
    for (const auto& [u, v] : {std::pair{0.5, 0.5}, std::pair{4.0, 7.25}, std::pair{8.5, 12.5}}) {
      const Ray a = window.ray(u, v), b = camera.ray(x0 + u * w / 9, y0 + v * h / 13);
      expectNear(a.origin, b.origin, 1e-9);
      expectNear(a.direction, b.direction, 1e-9);
      // The window's projection maps a point on the ray back to (u, v).
      const auto p = window.project(a.origin + 7.0 * a.direction);
      ASSERT_TRUE(p);
      EXPECT_NEAR((*p)[0], u, 1e-9);
      EXPECT_NEAR((*p)[1], v, 1e-9);
    }
  }
  EXPECT_THROW(windowCamera(orbitCamera(0, grid, 8, 10), 0, 0, 0, 4, 8, 10), Error);
}

TEST(CameraTest, NerfCameraLooksDownMinusZWithYUp) {
  // World = grid here; camera at (3, 3.5, 20) looking at the grid centre (3, 3.5, 2.5): down world -z.
  const GridSize grid{.x = 6, .y = 7, .z = 5};
  const Camera camera = lookAtCamera(grid, {3, 3.5, 20}, 40, 30, 0.6);
  EXPECT_TRUE(camera.perspective);
  expectNear(camera.forward(), {0, 0, -1}, 1e-3);
  const auto centre = camera.project({3, 3.5, 2.5});
  const auto right = camera.project({4, 3.5, 2.5});
  const auto up = camera.project({3, 4.5, 2.5});
  const auto behind = camera.project({3, 3.5, 30});
  ASSERT_TRUE(centre && right && up);
  EXPECT_NEAR((*centre)[0], 20, 1e-9);
  EXPECT_NEAR((*centre)[1], 15, 1e-9);
  EXPECT_GT((*right)[0], 20);  // world +x is image right
  EXPECT_LT((*up)[1], 15);     // world +y is image up (smaller row)
  EXPECT_FALSE(behind);
  // focal = w / (2 tan(fov / 2)): one unit at depth 17.5 spans focal / 17.5 pixels.
  EXPECT_NEAR((*right)[0] - 20, 40 / (2 * std::tan(0.3)) / 17.5, 1e-9);
  // A narrower render of the same camera scales pixel coordinates.
  const Camera half = lookAtCamera(grid, {3, 3.5, 20}, 20, 15, 0.6);
  EXPECT_NEAR((*half.project({4, 3.5, 2.5}))[0], 0.5 * (*right)[0], 1e-9);
}

class CalibrationFileTest : public ::testing::Test {
 protected:
  std::string errorFor(const std::string& json) const {
    const fs::path file = directory_ / "info.json";
    std::ofstream(file) << json;
    try {
      readCalibration(file);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  io::TemporaryFolder directory_{"calibration"};
};

TEST_F(CalibrationFileTest, BadFilesNameTheFieldAndExpectation) {
  const std::string box =
      R"("voxel_scale": [1, 1, 1], "voxel_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]])";
  const std::string view = R"({"file_name": "a.mp4", "camera_hw": [20, 10],
      "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]])";
  EXPECT_NE(errorFor("{ not json").find("not valid JSON"), std::string::npos);
  EXPECT_NE(errorFor("{" + box + "}").find("at least one view"), std::string::npos);
  EXPECT_NE(errorFor(R"({"train_videos": [)" + view + "}], " + box + "}")
                .find("field 'train_videos[0].camera_angle_x': expected to be present"),
            std::string::npos);
  const std::string good = view + R"(, "camera_angle_x": 0.5})";
  EXPECT_NE(errorFor(R"({"train_videos": [)" + good + R"(], "voxel_scale": [1, -1, 1],
      "voxel_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]})")
                .find("field 'voxel_scale': expected three positive box sizes"),
            std::string::npos);
  EXPECT_NE(errorFor(R"({"train_videos": [)" + good + R"(], "voxel_scale": [1, 1, 1],
      "voxel_matrix": [[1,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]})")
                .find("field 'voxel_matrix[0]': expected an array of 4 numbers"),
            std::string::npos);
  EXPECT_EQ(errorFor(R"({"train_videos": [)" + good + "], " + box + "}"), "");
}

TEST(ScalarFlowCalibrationTest, BoxProjectsIntoEveryCameraAndCentreCameraIsTheFrontView) {
  const fs::path info = scalarflowFolder() / "info.json";
  if (!fs::exists(info)) GTEST_SKIP() << info << " not present";
  const Calibration calibration = readCalibration(info);
  ASSERT_EQ(calibration.views.size(), 5u);
  const GridSize grid{.x = 64, .y = 96, .z = 64};
  for (const CalibratedView& view : calibration.views) {
    const Camera camera = calibratedCamera(view, calibration.box, grid, 270);
    ASSERT_EQ(camera.height, 480);
    const auto centre = camera.project(grid.centre());
    ASSERT_TRUE(centre) << view.fileName;
    EXPECT_GT((*centre)[0], 0.25 * 270) << view.fileName;
    EXPECT_LT((*centre)[0], 0.75 * 270) << view.fileName;
    EXPECT_GT((*centre)[1], 0.25 * 480) << view.fileName;
    EXPECT_LT((*centre)[1], 0.75 * 480) << view.fileName;
  }
  EXPECT_NEAR(orbitAngleOf(calibratedCamera(calibration.view("train02.mp4"), calibration.box, grid)), 0.0, 5.0);
  // The arc of cameras spans about 120 degrees around the front, in order.
  EXPECT_LT(orbitAngleOf(calibratedCamera(calibration.view("train00.mp4"), calibration.box, grid)), -40.0);
  EXPECT_GT(orbitAngleOf(calibratedCamera(calibration.view("train04.mp4"), calibration.box, grid)), 40.0);
}

TEST(ScalarFlowCalibrationTest, ProjectedBoxCentreLandsOnSmokeInEveryVideo) {
  const fs::path folder = scalarflowFolder();
  if (!fs::exists(folder / "info.json")) GTEST_SKIP() << folder << " not present";
  if (!media::findFfmpeg()) GTEST_SKIP() << "ffmpeg not installed";
  const Calibration calibration = readCalibration(folder / "info.json");
  const std::vector<render::ViewCheck> checks =
      render::checkCalibration(calibration, folder, 90, 135, {.x = 64, .y = 96, .z = 64});
  ASSERT_EQ(checks.size(), 5u);
  for (const render::ViewCheck& check : checks) {
    EXPECT_TRUE(check.centreInFrame) << check.fileName;
    // Smoke is bright on black: the centre window is many times the frame's mean.
    EXPECT_GT(check.brightnessAtCentre, 0.15f) << check.fileName;
    EXPECT_GT(check.brightnessAtCentre, 4 * check.frameMean) << check.fileName;
  }
}

}  // namespace
}  // namespace smokesvd::testing

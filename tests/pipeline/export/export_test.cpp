// `smokesvd export` of a reconstruction-shaped run (tests/harness/simulated_reconstruction.h): mantaflow's
// layout read back and advected, the NeRF cameras against the renderer's own images of a box, the OpenVDB
// files read back voxel for voxel with the OpenVDB API (in builds with OpenVDB), and bad inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "nets/io/json_file.h"
#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "pipeline/camera/calibration.h"
#include "pipeline/export/export_run.h"
#include "pipeline/export/nerf_cameras.h"
#include "pipeline/export/vdb_files.h"
#include "pipeline/export/world_placement.h"
#include "pipeline/media/image.h"
#include "pipeline/media/volume_file.h"
#include "pipeline/physics/advection.h"
#include "pipeline/render/render_images.h"
#include "pipeline/sim/frame_render.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/saved_run.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/simulated_reconstruction.h"

#if SMOKESVD_WITH_OPENVDB
#include <openvdb/openvdb.h>
#endif

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 3;
const GridSize kGrid{.x = 16, .y = 28, .z = 16};

const io::TemporaryFolder& root() {
  static const io::TemporaryFolder folder("export");
  return folder;
}

const fs::path& run() {
  static const fs::path folder = [] {
    const fs::path path = root() / "recon";
    writeSimulatedReconstruction(testContext(), path, kFrames, kGrid);
    return path;
  }();
  return folder;
}

exporters::ExportOptions options(exporters::Format format, const std::string& out) {
  exporters::ExportOptions o;
  o.source = run();
  o.out = root() / out;
  o.format = format;
  return o;
}

// A calibration that turns, shifts and scales the box (square pixels: the same size per cell along x and y).
fs::path tiltedCalibration() {
  const fs::path path = root() / "tilted.json";
  std::ofstream(path) << R"({"train_videos": [{"file_name": "a.mp4", "camera_angle_x": 0.5, "camera_hw": [100, 60],
    "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,2],[0,0,0,1]]}],
    "voxel_scale": [0.32, 0.56, 0.32],
    "voxel_matrix": [[0.8, 0, 0.6, 0.1], [0, 1, 0, -0.2], [-0.6, 0, 0.8, 0.3], [0, 0, 0, 1]]})";
  return path;
}

class ExportTest : public GpuTest {};

TEST_F(ExportTest, MantaflowFilesHaveItsLayoutAndAdvectAsTheRunDid) {
  const exporters::ExportResult r = exporters::runExport(options(exporters::Format::Mantaflow, "manta"));
  EXPECT_EQ(r.frames, kFrames);
  const fs::path out = root() / "manta";
  const sim::SavedRun saved = sim::readSavedRun(run());
  for (int t = 0; t < kFrames; ++t) {
    for (const auto& [name, channels] : {std::pair{"density", 1}, {"velocity", 3}, {"inflow", 1}}) {
      const std::map<std::string, io::NpyArray> arrays = io::readNpz(out / (std::string(name) + "_" + sim::frameName(t) + ".npz"));
      ASSERT_EQ(arrays.size(), 1u);
      const io::NpyArray& a = arrays.at("arr_0");
      EXPECT_EQ(a.dtype, io::DType::Float32);
      EXPECT_EQ(a.shape, (Shape{kGrid.z, kGrid.y, kGrid.x, channels})) << name;
      EXPECT_EQ(a.floats, io::readNpzMember(saved.field(name, t), name).floats) << name << " " << t;
    }
  }
  const io::NpyArray flags = io::readNpzMember(out / "flags.npz", "arr_0");
  EXPECT_EQ(flags.dtype, io::DType::Int32);
  EXPECT_EQ(flags.shape, (Shape{kGrid.z, kGrid.y, kGrid.x, 1}));
  EXPECT_EQ(media::readDensityVolume(out / "density_0001.npz").grid, kGrid) << "smokesvd render reads it back";
  // The MAC convention is the one our advection, equal to mantaflow's on ../shared/testdata/mantaflow, reads:
  // density[2] = A(density[1], velocity[1]) + inflow[2] from the exported files alone.
  auto planar = [&](const std::vector<float>& interleaved) {
    std::vector<float> p(interleaved.size());
    const std::size_t cells = interleaved.size() / 3;
    for (std::size_t c = 0; c < cells; ++c)
      for (std::size_t a = 0; a < 3; ++a) p[a * cells + c] = interleaved[3 * c + a];
    return p;
  };
  Stream stream(context());
  const physics::FlagGrid grid(stream, Tensor::fromHost(context(), kGrid.volume(), flags.toFloat()));
  const Tensor d = Tensor::fromHost(context(), kGrid.volume(), io::readNpzMember(out / "density_0001.npz", "arr_0").floats);
  const Tensor u = Tensor::fromHost(context(), kGrid.vector(), planar(io::readNpzMember(out / "velocity_0001.npz", "arr_0").floats));
  const Tensor in = Tensor::fromHost(context(), kGrid.volume(), io::readNpzMember(out / "inflow_0002.npz", "arr_0").floats);
  const Tensor next(context(), kGrid.volume());
  physics::advect(stream, grid, d, u, &in, {}, next);
  stream.submit();
  EXPECT_EQ(next.download(), io::readNpzMember(out / "density_0002.npz", "arr_0").floats);
  EXPECT_EQ(io::readJsonFile(out / "export.json")["format"], "mantaflow");
}

// Pixel coordinates of a world point through a transforms.json camera, as nerfstudio reads it: OpenGL
// camera-to-world, turned to OpenCV (x right, y down, z forward), u = fx x / z + cx.
glm::dvec2 nerfProject(const nlohmann::json& transforms, const nlohmann::json& frame, const glm::dvec3& world) {
  glm::dmat4 c2w;
  for (int r = 0; r < 4; ++r)
    for (int col = 0; col < 4; ++col) c2w[col][r] = frame["transform_matrix"][r][col].get<double>();
  const glm::dvec3 p = glm::dvec3(glm::inverse(c2w) * glm::dvec4(world, 1.0));
  const glm::dvec3 cv(p.x, -p.y, -p.z);
  return {transforms["fl_x"].get<double>() * cv.x / cv.z + transforms["cx"].get<double>(),
          transforms["fl_y"].get<double>() * cv.y / cv.z + transforms["cy"].get<double>()};
}

// Signed distance (pixels, > 0 inside) from q to the convex hull of `points`.
double hullDistance(std::vector<glm::dvec2> points, const glm::dvec2& q) {
  std::sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  auto cross = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<glm::dvec2> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], points[i - 1]) <= 0) --k;
    hull[k++] = points[i - 1];
  }
  hull.resize(k - 1);
  double distance = 1e300;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const glm::dvec2 a = hull[i], b = hull[(i + 1) % hull.size()];
    distance = std::min(distance, cross(a, b, q) / glm::length(b - a));
  }
  return distance;
}

// The cameras of frame_0000/transforms.json put a box of smoke where the renderer draws it through the
// run's orthographic views: every pixel more than 1.5 pixels from the projected box's outline is lit exactly
// when it lies inside it.
void expectCamerasReprojectTheBox(const fs::path& out, const exporters::WorldPlacement& placement) {
  const nlohmann::json transforms = io::readJsonFile(out / "frame_0000" / "transforms.json");
  const sim::Scene scene = sim::readScene(run() / "scene.json");
  const std::vector<Camera> views =
      orbitCameras(orbitAngles(scene.render.views), kGrid, scene.render.width, scene.render.height);
  ASSERT_EQ(transforms["frames"].size(), views.size());
  const int lo[3] = {3, 4, 2}, hi[3] = {11, 20, 13};  // cells of the box: [lo, hi) along x, y, z
  std::vector<float> box(static_cast<std::size_t>(kGrid.cells()), 0.0f);
  for (int64_t k = lo[2]; k < hi[2]; ++k)
    for (int64_t j = lo[1]; j < hi[1]; ++j)
      for (int64_t i = lo[0]; i < hi[0]; ++i) box[static_cast<std::size_t>((k * kGrid.y + j) * kGrid.x + i)] = 1.0f;
  const std::vector<media::Image> images =
      render::renderImages(testContext(), Tensor::fromHost(testContext(), kGrid.volume(), box), views, sim::renderSettings(scene.render));
  int compared = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const nlohmann::json& frame = transforms["frames"][v];
    std::vector<glm::dvec2> corners;
    for (int c = 0; c < 8; ++c) {
      const glm::dvec4 grid(c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2], 1.0);
      corners.push_back(nerfProject(transforms, frame, glm::dvec3(placement.gridToWorld * grid)));
    }
    for (int row = 0; row < images[v].height; ++row)
      for (int column = 0; column < images[v].width; ++column) {
        const double inside = hullDistance(corners, {column + 0.5, row + 0.5});
        if (std::abs(inside) < 1.5) continue;
        ++compared;
        ASSERT_EQ(images[v].at(row, column) > 0.05f, inside > 0) << "view " << v << ", row " << row << ", column " << column;
      }
    // The whole grid's box spans the orthographic window: its front corners land on the image's edges at view 0.
    if (v == 0) {
      const glm::dvec2 corner = nerfProject(transforms, frame, glm::dvec3(placement.gridToWorld * glm::dvec4(0, 0, 8, 1)));
      EXPECT_NEAR(corner.x, 0.0, 0.25);
      EXPECT_NEAR(corner.y, static_cast<double>(kGrid.y), 0.25);
    }
  }
  EXPECT_GT(compared, 4000);
  EXPECT_LE(transforms["smokesvd"]["max_reprojection_error_pixels"].get<double>(), 0.25 + 1e-9);
}

TEST_F(ExportTest, NerfCamerasPutTheBoxWhereTheRendererDrawsIt) {
  const exporters::ExportOptions o = options(exporters::Format::Nerf, "nerf");
  exporters::runExport(o);
  const fs::path frame = o.out / "frame_0002";
  for (const char* f : {"transforms.json", "transforms_train.json", "transforms_test.json", "images/view_15.png"})
    EXPECT_TRUE(fs::exists(frame / f)) << f;
  const nlohmann::json transforms = io::readJsonFile(frame / "transforms.json");
  EXPECT_EQ(transforms["camera_model"], "OPENCV");
  EXPECT_EQ(transforms["w"], 16);
  EXPECT_EQ(transforms["h"], 28);
  EXPECT_EQ(transforms["frames"][3]["file_path"], "images/view_03.png");
  EXPECT_DOUBLE_EQ(transforms["fl_x"].get<double>(), transforms["fl_y"].get<double>());
  const nlohmann::json synthetic = io::readJsonFile(frame / "transforms_train.json");
  EXPECT_EQ(synthetic["frames"][3]["file_path"], "./images/view_03");
  EXPECT_NEAR(synthetic["camera_angle_x"].get<double>(), 2 * std::atan(8.0 / transforms["fl_x"].get<double>()), 1e-12);
  EXPECT_TRUE(io::readJsonFile(frame / "transforms_test.json")["frames"].empty());
  // 8-bit RGB copies of the run's 16-bit renders.
  const media::Image copy = media::readPng(frame / "images" / "view_05.png");
  const media::Image original = media::readPng(run() / "renders" / "view_05" / "0002.png");
  ASSERT_EQ(copy.values.size(), original.values.size());
  for (std::size_t i = 0; i < copy.values.size(); ++i) ASSERT_NEAR(copy.values[i], original.values[i], 0.5 / 255 + 1e-6);
  expectCamerasReprojectTheBox(o.out, exporters::placementOf(sim::readSavedRun(run()), std::nullopt, false));
}

TEST_F(ExportTest, NerfCamerasFollowACalibratedAndAZUpWorld) {
  exporters::ExportOptions o = options(exporters::Format::Nerf, "nerf-tilted");
  o.calibration = tiltedCalibration();
  o.zUp = true;
  exporters::runExport(o);
  const exporters::WorldPlacement placement = exporters::placementOf(sim::readSavedRun(run()), o.calibration, true);
  // The z-up world: grid up (+y) is world +z.
  const glm::dvec3 up = placement.linear() * glm::dvec3(0, 1, 0);
  EXPECT_NEAR(up.x, 0, 1e-12);
  EXPECT_NEAR(up.y, 0, 1e-12);
  EXPECT_GT(up.z, 0);
  expectCamerasReprojectTheBox(o.out, placement);
}

TEST_F(ExportTest, NonSquarePixelsHaveNoNerfSyntheticFiles) {
  const fs::path calibration = root() / "stretched.json";
  std::ofstream(calibration) << R"({"test_videos": [{"file_name": "a.mp4", "camera_angle_x": 0.5, "camera_hw": [100, 60],
    "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,2],[0,0,0,1]]}],
    "voxel_scale": [0.32, 0.42, 0.32], "voxel_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]})";
  exporters::ExportOptions o = options(exporters::Format::Nerf, "nerf-stretched");
  o.calibration = calibration;
  exporters::runExport(o);
  EXPECT_TRUE(fs::exists(o.out / "frame_0000" / "transforms.json"));
  EXPECT_FALSE(fs::exists(o.out / "frame_0000" / "transforms_train.json"));
  const nlohmann::json transforms = io::readJsonFile(o.out / "frame_0000" / "transforms.json");
  EXPECT_GT(std::abs(transforms["fl_x"].get<double>() - transforms["fl_y"].get<double>()), 1.0);
  expectCamerasReprojectTheBox(o.out, exporters::placementOf(sim::readSavedRun(run()), calibration, false));
}

TEST_F(ExportTest, TheCameraErrorSetsTheDistance) {
  const exporters::WorldPlacement placement = exporters::placementOf(sim::readSavedRun(run()), std::nullopt, false);
  const std::vector<Camera> views = orbitCameras(orbitAngles(16), kGrid, 16, 28);
  const exporters::PinholeApproximation loose = exporters::pinholeCameras(views, kGrid, placement, 1.0);
  const exporters::PinholeApproximation tight = exporters::pinholeCameras(views, kGrid, placement, 0.05);
  EXPECT_LE(loose.maxErrorPixels, 1.0 + 1e-9);
  EXPECT_GT(loose.maxErrorPixels, 0.5);
  EXPECT_LE(tight.maxErrorPixels, 0.05 + 1e-9);
  EXPECT_GT(tight.distance, 10 * loose.distance);
  // Every grid point of the box through the pinhole camera against the orthographic view itself.
  for (std::size_t v = 0; v < views.size(); ++v)
    for (double x = 0; x <= 16; x += 2)
      for (double y = 0; y <= 28; y += 4)
        for (double z = 0; z <= 16; z += 2) {
          const auto ortho = views[v].project({x, y, z});
          ASSERT_TRUE(ortho.has_value());
          const glm::dvec2 pinhole =
              exporters::projectPinhole(loose.cameras[v], glm::dvec3(placement.gridToWorld * glm::dvec4(x, y, z, 1)));
          ASSERT_LE(glm::length(pinhole - glm::dvec2((*ortho)[0], (*ortho)[1])), 1.0 + 1e-9) << "view " << v;
        }
}

#if SMOKESVD_WITH_OPENVDB

TEST_F(ExportTest, VdbFilesReadBackVoxelForVoxel) {
  exporters::ExportOptions o = options(exporters::Format::Vdb, "vdb");
  o.calibration = tiltedCalibration();
  exporters::runExport(o);
  const sim::SavedRun saved = sim::readSavedRun(run());
  const exporters::WorldPlacement placement = exporters::placementOf(saved, o.calibration, false);
  openvdb::initialize();
  for (int t = 0; t < kFrames; ++t) {
    openvdb::io::File file((o.out / ("frame_" + sim::frameName(t) + ".vdb")).string());
    file.open();
    const openvdb::FloatGrid::Ptr density = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
    const openvdb::Vec3SGrid::Ptr velocity = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("velocity"));
    EXPECT_EQ(file.getMetadata()->metaValue<int32_t>("smokesvd_frame"), t);
    file.close();
    ASSERT_TRUE(density && velocity);
    EXPECT_EQ(density->getGridClass(), openvdb::GRID_FOG_VOLUME);
    EXPECT_EQ(velocity->getVectorType(), openvdb::VEC_INVARIANT);
    const std::vector<float> expectedDensity = saved.density(t);
    const std::vector<float> expectedVelocity = exporters::worldVelocity(saved.velocity(t), kGrid, placement, saved.frameRate);
    const openvdb::FloatGrid::ConstAccessor d = density->getConstAccessor();
    const openvdb::Vec3SGrid::ConstAccessor u = velocity->getConstAccessor();
    for (int k = -1; k <= kGrid.z; ++k)
      for (int j = -1; j <= kGrid.y; ++j)
        for (int i = -1; i <= kGrid.x; ++i) {
          const openvdb::Coord ijk(i, j, k);
          const bool inGrid = i >= 0 && j >= 0 && k >= 0 && i < kGrid.x && j < kGrid.y && k < kGrid.z;
          const std::size_t c = inGrid ? static_cast<std::size_t>((k * kGrid.y + j) * kGrid.x + i) : 0;
          ASSERT_EQ(d.getValue(ijk), inGrid ? expectedDensity[c] : 0.0f) << i << " " << j << " " << k;
          for (int a = 0; a < 3; ++a)
            ASSERT_EQ(u.getValue(ijk)[a], inGrid ? expectedVelocity[3 * c + static_cast<std::size_t>(a)] : 0.0f) << i << " " << j << " " << k;
        }
    // Voxel (i, j, k) is centred at grid point (i + 1/2, j + 1/2, k + 1/2) of the placement.
    for (const openvdb::Coord ijk : {openvdb::Coord(0, 0, 0), openvdb::Coord(15, 27, 15), openvdb::Coord(3, 20, 9)}) {
      const openvdb::Vec3d world = density->transform().indexToWorld(ijk);
      const glm::dvec3 expected(placement.gridToWorld * glm::dvec4(ijk.x() + 0.5, ijk.y() + 0.5, ijk.z() + 0.5, 1));
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(world[a], expected[a], 1e-12);
    }
  }
  // Velocity in world units per second: one cell per step along x is (world length of a cell along x) x 24/s.
  std::vector<float> unitX(static_cast<std::size_t>(3 * kGrid.cells()), 0.0f);
  std::fill(unitX.begin(), unitX.begin() + kGrid.cells(), 1.0f);
  const std::vector<float> world = exporters::worldVelocity(unitX, kGrid, placement, 24);
  const std::size_t inside = static_cast<std::size_t>((5 * kGrid.y + 5) * kGrid.x + 5);
  const glm::dvec3 v(world[3 * inside], world[3 * inside + 1], world[3 * inside + 2]);
  EXPECT_NEAR(glm::length(v), 0.32 / 16 * 24, 1e-6);
}

#else

TEST_F(ExportTest, VdbWithoutOpenVdbIsAClearErrorThatWritesNothing) {
  const exporters::ExportOptions o = options(exporters::Format::Vdb, "vdb");
  try {
    exporters::runExport(o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("built without OpenVDB"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(o.out));
}

#endif

TEST_F(ExportTest, BadPlacesAndSourcesAreErrorsThatTouchNothing) {
  auto message = [](const exporters::ExportOptions& o) {
    try {
      exporters::runExport(o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  exporters::ExportOptions o = options(exporters::Format::Mantaflow, "busy");
  fs::create_directories(o.out);
  std::ofstream(o.out / "notes.txt") << "mine";
  EXPECT_NE(message(o).find("is not empty and holds no export"), std::string::npos) << message(o);
  EXPECT_TRUE(fs::exists(o.out / "notes.txt"));
  o.out = "/proc/smokesvd-export";
  EXPECT_NE(message(o).find("cannot create the output folder"), std::string::npos) << message(o);
  o.out = root() / "busy" / "notes.txt" / "out";
  EXPECT_NE(message(o).find("cannot create the output folder"), std::string::npos) << message(o);
  o.out = root() / "again";
  EXPECT_EQ(message(o), "no error");
  EXPECT_NE(message(o).find("holds an export; --overwrite replaces it"), std::string::npos) << message(o);
  o.overwrite = true;
  EXPECT_EQ(message(o), "no error");
  o.source = root() / "busy";
  o.out = root() / "never";
  EXPECT_NE(message(o).find("not a run folder"), std::string::npos) << message(o);
  o.source = run();
  o.calibration = root() / "missing.json";
  EXPECT_NE(message(o).find("which is not there; give its place with --calibration"), std::string::npos) << message(o);
  EXPECT_FALSE(fs::exists(root() / "never"));
}

}  // namespace
}  // namespace smokesvd::testing

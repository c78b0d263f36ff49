#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "nets/io/temporary_folder.h"
#include "pipeline/sim/domain.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/scene.h"
#include "runtime/error.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;
using sim::Scene;

// A fresh folder `name` inside this program's temporary folder (removed when the program ends).
fs::path scratchDirectory(const std::string& name) {
  static const io::TemporaryFolder root("scene");
  const fs::path path = root / name;
  fs::remove_all(path);
  fs::create_directories(path);
  return path;
}

// The message of the Error that parsing `text` (as file "bad.json") throws, or "" if it parses.
std::string parseError(const std::string& text) {
  try {
    sim::parseScene(nlohmann::json::parse(text), "bad.json");
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(SceneJson, RandomScenesRoundTripThroughFiles) {
  const fs::path directory = scratchDirectory("round_trip");
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const Scene scene = sim::randomScene(seed, {.x = 32, .y = 56, .z = 32}, 60);
    sim::writeScene(directory / "scene.json", scene);
    EXPECT_EQ(sim::readScene(directory / "scene.json"), scene) << "seed " << seed;
  }
}

TEST(SceneJson, EveryFieldRoundTrips) {
  const fs::path directory = scratchDirectory("every_field");
  Scene scene = sim::randomScene(3, {.x = 20, .y = 30, .z = 24}, 12);
  scene.stepsPerFrame = 2;
  scene.dt = 0.5;
  scene.boundaries = {sim::Boundary::Open, sim::Boundary::Wall, sim::Boundary::Wall,
                      sim::Boundary::Open, sim::Boundary::Open, sim::Boundary::Wall};
  scene.advection = physics::AdvectionScheme::SemiLagrangian;
  scene.advectionStrength = 0.75;
  scene.pressureTolerance = 1e-3;
  scene.pressureMaxIterations = 42;
  scene.gravity = {0.1, -2, 0.3};
  scene.windWeighting = sim::WindWeighting::Uniform;
  scene.forceFields.push_back({directory / "force.npz", "f", 0.25, {2, 7}});
  sim::Obstacle box;
  box.shape.kind = physics::SourceShape::Box;
  box.shape.centre = {10, 15, 12};
  box.shape.size = {2, 3, 4};
  box.frames = {5, -1};
  scene.obstacles.push_back(box);
  sim::Source cylinder;
  cylinder.shape.kind = physics::SourceShape::Cylinder;
  cylinder.shape.centre = {5, 4, 6};
  cylinder.shape.size = {2.5, 1.5, 0};
  cylinder.shape.axis = {0, 1, 1};
  cylinder.mode = physics::InflowMode::Add;
  cylinder.density.points = {{0, 0.5}, {4, 1.5}, {9.5, 0.25}};
  cylinder.velocity = sim::Keyframes<Vec3>{{{0, {0, 1, 0}}, {6, {0.5, 0.5, 0}}}};
  cylinder.frames = {0, 8};
  scene.sources.push_back(cylinder);
  scene.render.lightDirection = Vec3{-1, 2, -1};
  scene.render.lightIntensity = 0.8;
  scene.render.views = 4;
  sim::writeScene(directory / "scene.json", scene);
  EXPECT_EQ(sim::readScene(directory / "scene.json"), scene);
}

TEST(SceneJson, MinimalSceneTakesDefaults) {
  const Scene scene = sim::parseScene(nlohmann::json::parse(R"({"resolution": [8, 12, 10], "frames": 3})"), "min.json");
  EXPECT_EQ(scene.render.width, 8);
  EXPECT_EQ(scene.render.height, 12);
  EXPECT_EQ(scene.boundaries[3], sim::Boundary::Open);
  EXPECT_TRUE(scene.sources.empty());
  EXPECT_FALSE(scene.tracksTemperature());
}

TEST(SceneJson, BadScenesNameTheFileTheFieldAndWhatWasExpected) {
  struct Case {
    std::string json, mentions;
  };
  const std::string base = R"("resolution": [8, 12, 10], "frames": 3)";
  const std::vector<Case> cases = {
      {"{}", "missing field 'resolution'"},
      {R"({"resolution": [8, 12], "frames": 3})", "field 'resolution': expected three cell counts [x, y, z]"},
      {R"({"resolution": [8, 2, 10], "frames": 3})", "field 'resolution[1]': expected an integer in [3, 1024]"},
      {R"({"resolution": [8, 12, 10], "frames": 0})", "field 'frames': expected an integer in [1, 1000000]"},
      {"{" + base + R"(, "framez": 3})", "unknown field 'framez'"},
      {"{" + base + R"(, "sources": [{"shape": "cone", "centre": [1, 2, 3]}]})",
       R"(field 'sources[0].shape': expected one of "sphere", "box", "cylinder", got "cone")"},
      {"{" + base + R"(, "sources": [{"shape": "sphere", "centre": [1, 2, 3], "radius": -1}]})",
       "field 'sources[0].radius': expected a number above 0 and at most 100000.0, got -1"},
      {"{" + base + R"(, "sources": [{"shape": "sphere", "centre": [1, 2]}]})",
       "field 'sources[0].centre': expected three numbers [x, y, z]"},
      {"{" + base + R"(, "sources": [{"shape": "box", "centre": [1, 2, 3]}]})", "missing field 'sources[0].half_size'"},
      {"{" + base + R"(, "sources": [{"shape": "sphere", "centre": [1, 2, 3], "radius": 1, "density": [[0, 1], [0, 2]]}]})",
       "field 'sources[0].density[1][0]': expected a frame after the previous keyframe's"},
      {"{" + base + R"(, "boundaries": {"y_high": "leaky"}})", R"(field 'boundaries.y_high': expected one of "wall", "open")"},
      {"{" + base + R"(, "pressure": {"tolerance": 2}})", "field 'pressure.tolerance': expected a number in"},
      {"{" + base + R"(, "wind": {"acceleration": "east"}})", "field 'wind.acceleration'"},
      {"{" + base + R"(, "obstacles": [{"shape": "sphere", "centre": [1, 2, 3], "radius": 1, "frames": [5, 2]}]})",
       "field 'obstacles[0].frames': expected [first, last] with last > first"},
      {"{" + base + R"(, "render": {"views": 0}})", "field 'render.views': expected an integer in [1, 360]"},
  };
  for (const Case& c : cases) {
    const std::string message = parseError(c.json);
    EXPECT_NE(message.find("bad.json: "), std::string::npos) << c.json << "\n -> " << message;
    EXPECT_NE(message.find(c.mentions), std::string::npos) << c.json << "\n -> " << message;
  }
}

TEST(SceneJson, UnreadableFilesAreClearErrors) {
  const fs::path directory = scratchDirectory("unreadable");
  std::ofstream(directory / "broken.json") << "{\"resolution\": [8, 12";
  try {
    sim::readScene(directory / "broken.json");
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("broken.json: not valid JSON"), std::string::npos) << error.what();
  }
  EXPECT_THROW(sim::readScene(directory / "absent.json"), Error);
}

TEST(SceneKeyframes, PiecewiseLinearAndConstantOutside) {
  const sim::Keyframes<double> k{{{2, 1.0}, {6, 3.0}, {10, -1.0}}};
  EXPECT_DOUBLE_EQ(k.at(0), 1.0);
  EXPECT_DOUBLE_EQ(k.at(4), 2.0);
  EXPECT_DOUBLE_EQ(k.at(8), 1.0);
  EXPECT_DOUBLE_EQ(k.at(20), -1.0);
  EXPECT_DOUBLE_EQ(sim::Keyframes<double>::constant(0.5).at(99), 0.5);
}

TEST(SceneDomain, BoundariesAndObstaclesBecomeFlags) {
  Scene scene;
  scene.resolution = {.x = 9, .y = 11, .z = 7};
  scene.frames = 10;
  sim::Obstacle sphere;
  sphere.shape.centre = {4.5, 5.5, 3.5};
  sphere.shape.size = {1.2, 0, 0};
  sphere.frames = {4, -1};
  scene.obstacles.push_back(sphere);
  auto at = [&](const std::vector<float>& flags, int i, int j, int k) { return flags[i + 9 * (j + 11 * k)]; };
  const std::vector<float> early = sim::sceneFlags(scene, 0), late = sim::sceneFlags(scene, 4);
  EXPECT_EQ(at(early, 0, 5, 3), 2.0f);   // x_low wall
  EXPECT_EQ(at(early, 4, 10, 3), 4.0f);  // open top
  EXPECT_EQ(at(early, 0, 10, 3), 2.0f);  // wall wins at an edge with the open top
  EXPECT_EQ(at(early, 4, 5, 3), 1.0f);   // no obstacle yet
  EXPECT_EQ(at(late, 4, 5, 3), 2.0f);    // sphere centre
  EXPECT_EQ(at(late, 4, 7, 3), 1.0f);    // outside the sphere
  EXPECT_TRUE(sim::obstaclesChangeAt(scene, 4));
  EXPECT_FALSE(sim::obstaclesChangeAt(scene, 5));
}

TEST(RandomScenes, SameSeedSameSceneOtherSeedOtherScene) {
  const GridSize paper{.x = 64, .y = 112, .z = 64};
  EXPECT_EQ(sim::randomScene(11, paper, 150), sim::randomScene(11, paper, 150));
  EXPECT_NE(sim::randomScene(11, paper, 150), sim::randomScene(12, paper, 150));
}

// Over many seeds every kind of scene appears, sources stay low in the domain and inside it, and the
// look varies.
TEST(RandomScenes, TheDistributionCoversPlumesPuffsJetsAndTwoSources) {
  int puffs = 0, jets = 0, twins = 0, lit = 0;
  double minAbsorption = 1e9, maxAbsorption = 0;
  for (uint64_t seed = 0; seed < 200; ++seed) {
    const Scene scene = sim::randomScene(seed, {.x = 32, .y = 56, .z = 32}, 60);
    ASSERT_GE(scene.sources.size(), 1u);
    ASSERT_LE(scene.sources.size(), 2u);
    twins += scene.sources.size() == 2;
    for (const sim::Source& source : scene.sources) {
      const Vec3& centre = source.shape.centre;
      EXPECT_GT(centre[0], 0.0);
      EXPECT_LT(centre[0], 32.0);
      EXPECT_GT(centre[2], 0.0);
      EXPECT_LT(centre[2], 32.0);
      EXPECT_GT(centre[1], 0.0);
      EXPECT_LT(centre[1], 0.25 * 56);
      puffs += source.frames.last > 0 && scene.sources.size() == 1;
      if (source.velocity) {
        const Vec3 v = source.velocity->at(0);
        jets += std::hypot(v[0], v[2]) > 0.1;
      }
    }
    EXPECT_GT(scene.densityBuoyancy, 0.0);
    lit += scene.render.lightDirection.has_value();
    minAbsorption = std::min(minAbsorption, scene.render.absorption);
    maxAbsorption = std::max(maxAbsorption, scene.render.absorption);
  }
  EXPECT_GT(puffs, 10);
  EXPECT_GT(jets, 20);
  EXPECT_GT(twins, 25);
  EXPECT_GT(lit, 40);
  EXPECT_LT(lit, 110);
  EXPECT_LT(minAbsorption, 0.4);
  EXPECT_GT(maxAbsorption, 0.8);
}

}  // namespace
}  // namespace smokesvd::testing

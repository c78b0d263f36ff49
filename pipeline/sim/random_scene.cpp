#include "pipeline/sim/random_scene.h"

#include <cmath>
#include <numbers>
#include <random>

namespace smokesvd::sim {
namespace {

class Draw {
 public:
  explicit Draw(uint64_t seed) : generator_(seed) {}
  double uniform(double low, double high) {
    const double unit = static_cast<double>(generator_() >> 11) * 0x1.0p-53;
    return low + (high - low) * unit;
  }
  bool chance(double probability) { return uniform(0, 1) < probability; }
  uint32_t seed() { return static_cast<uint32_t>(generator_() & 0xffffff); }

 private:
  std::mt19937_64 generator_;
};

}  // namespace

Scene randomScene(uint64_t seed, const std::array<int64_t, 3>& resolution, int frames) {
  Draw draw(seed);
  Scene scene;
  scene.seed = seed;
  scene.resolution = resolution;
  scene.frames = frames;
  const double nx = static_cast<double>(resolution[0]), ny = static_cast<double>(resolution[1]),
               nz = static_cast<double>(resolution[2]);
  const double scale = nx / 64.0;  // lengths and accelerations are drawn for a 64-cell-wide grid

  Source source;
  const double kind = draw.uniform(0, 1);
  source.shape.centre = {nx * draw.uniform(0.35, 0.65), ny * draw.uniform(0.06, 0.12), nz * draw.uniform(0.35, 0.65)};
  if (kind < 0.5) {
    source.shape.kind = physics::SourceShape::Sphere;
    source.shape.size = {nx * draw.uniform(0.08, 0.15), 0, 0};
  } else if (kind < 0.8) {
    source.shape.kind = physics::SourceShape::Cylinder;
    source.shape.size = {nx * draw.uniform(0.08, 0.15), ny * draw.uniform(0.015, 0.04), 0};
  } else {
    source.shape.kind = physics::SourceShape::Box;
    source.shape.size = {nx * draw.uniform(0.06, 0.13), ny * draw.uniform(0.015, 0.04), nz * draw.uniform(0.06, 0.13)};
  }
  source.density = Keyframes<double>::constant(draw.uniform(0.8, 1.2));
  source.noise.amplitude = draw.uniform(0.2, 0.6);
  source.noise.scale = scale * draw.uniform(2.0, 5.0);
  source.noise.velocity = {0, scale * draw.uniform(0.3, 1.0), 0};
  source.noise.seed = draw.seed();
  if (draw.chance(0.5)) source.velocity = Keyframes<Vec3>::constant({0, scale * draw.uniform(0.2, 0.8), 0});

  scene.densityBuoyancy = scale * draw.uniform(0.035, 0.07);
  if (draw.chance(0.5)) {
    source.temperature = Keyframes<double>::constant(draw.uniform(0.5, 1.0));
    scene.temperatureBuoyancy = scale * draw.uniform(0.015, 0.035);
  }
  scene.sources.push_back(source);

  // Wind: a horizontal acceleration of the smoke that turns and changes strength at three keyframes.
  const double windMagnitude = scene.densityBuoyancy * draw.uniform(0.0, 0.4);
  double direction = draw.uniform(0, 2 * std::numbers::pi);
  scene.wind.points.clear();
  for (int k = 0; k < 3; ++k) {
    const double strength = windMagnitude * draw.uniform(0.5, 1.0);
    scene.wind.points.emplace_back(frames * k / 2.0, Vec3{strength * std::cos(direction), 0, strength * std::sin(direction)});
    direction += draw.uniform(-0.8, 0.8);
  }
  scene.windWeighting = WindWeighting::Density;
  scene.vorticity = draw.uniform(0.0, 0.15);

  if (draw.chance(0.3)) {
    Obstacle obstacle;
    obstacle.shape.kind = physics::SourceShape::Sphere;
    obstacle.shape.centre = {source.shape.centre[0] + nx * draw.uniform(-0.12, 0.12), ny * draw.uniform(0.4, 0.6),
                             source.shape.centre[2] + nz * draw.uniform(-0.12, 0.12)};
    obstacle.shape.size = {nx * draw.uniform(0.08, 0.14), 0, 0};
    scene.obstacles.push_back(obstacle);
  }
  scene.render.width = static_cast<int>(resolution[0]);
  scene.render.height = static_cast<int>(resolution[1]);
  return scene;
}

}  // namespace smokesvd::sim

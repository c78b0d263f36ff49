#include "pipeline/sim/random_scene.h"

#include <algorithm>
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

struct Extent {
  double nx, ny, nz;
  double scale;  // lengths and speeds are drawn for a 64-cell-wide grid and scaled by this
};

// A noisy source of random shape and size at (fx, fz) across the floor, at a random height.
Source drawSource(Draw& draw, const Extent& e, double fx, double fz) {
  Source source;
  source.shape.centre = {e.nx * fx, e.ny * draw.uniform(0.05, 0.22), e.nz * fz};
  const double kind = draw.uniform(0, 1);
  const double radius = e.nx * draw.uniform(0.06, 0.16);
  if (kind < 0.5) {
    source.shape.kind = physics::SourceShape::Sphere;
    source.shape.size = {radius, 0, 0};
  } else if (kind < 0.8) {
    source.shape.kind = physics::SourceShape::Cylinder;
    source.shape.size = {radius, e.ny * draw.uniform(0.015, 0.04), 0};
  } else {
    source.shape.kind = physics::SourceShape::Box;
    source.shape.size = {radius * draw.uniform(0.7, 1.0), e.ny * draw.uniform(0.015, 0.04), radius * draw.uniform(0.7, 1.0)};
  }
  source.density = Keyframes<double>::constant(draw.uniform(0.6, 1.4));
  source.noise.amplitude = draw.uniform(0.2, 0.6);
  source.noise.scale = e.scale * draw.uniform(2.0, 5.0);
  source.noise.velocity = {0, e.scale * draw.uniform(0.3, 1.0), 0};
  source.noise.seed = draw.seed();
  if (draw.chance(0.5)) source.velocity = Keyframes<Vec3>::constant({0, e.scale * draw.uniform(0.2, 0.8), 0});
  return source;
}

void drawSources(Draw& draw, const Extent& e, int frames, Scene& scene) {
  const double kind = draw.uniform(0, 1);
  if (kind < 0.40) {  // a plume: one source that keeps flowing
    scene.sources.push_back(drawSource(draw, e, draw.uniform(0.3, 0.7), draw.uniform(0.3, 0.7)));
  } else if (kind < 0.55) {  // a puff: the inflow stops
    Source source = drawSource(draw, e, draw.uniform(0.3, 0.7), draw.uniform(0.3, 0.7));
    source.frames = {0, std::max(1, static_cast<int>(std::lround(frames * draw.uniform(0.15, 0.5))))};
    source.velocity = Keyframes<Vec3>::constant({0, e.scale * draw.uniform(0.4, 1.0), 0});
    scene.sources.push_back(source);
  } else if (kind < 0.75) {  // a jet: the source blows sideways, from the side it points away from
    const double direction = draw.uniform(0, 2 * std::numbers::pi);
    const double dx = std::cos(direction), dz = std::sin(direction);
    Source source = drawSource(draw, e, 0.5 - 0.22 * dx, 0.5 - 0.22 * dz);
    const double speed = e.scale * draw.uniform(0.4, 1.2);
    source.velocity = Keyframes<Vec3>::constant({speed * dx, e.scale * draw.uniform(0.0, 0.4), speed * dz});
    scene.sources.push_back(source);
  } else {  // two sources, the second starting later
    const bool alongX = draw.chance(0.5);
    const double a = draw.uniform(0.22, 0.4), b = draw.uniform(0.6, 0.78), across = draw.uniform(0.35, 0.65);
    scene.sources.push_back(drawSource(draw, e, alongX ? a : across, alongX ? across : a));
    Source second = drawSource(draw, e, alongX ? b : across, alongX ? across : b);
    second.frames = {static_cast<int>(std::lround(frames * draw.uniform(0.0, 0.4))), -1};
    scene.sources.push_back(second);
  }
}

// Per-scene looks: how thick the smoke appears (absorption, scaled with the grid so a scene looks alike
// at every resolution), and either even ambient light or a directional light with self-shadowing.
void drawRender(Draw& draw, const Extent& e, Scene& scene) {
  scene.render.absorption = (64.0 / e.nx) * draw.uniform(0.15, 0.45);
  if (draw.chance(0.35)) {
    const double azimuth = draw.uniform(0, 2 * std::numbers::pi);
    const double elevation = draw.uniform(15.0, 60.0) * std::numbers::pi / 180.0;
    scene.render.lightDirection = Vec3{std::cos(elevation) * std::cos(azimuth), std::sin(elevation),
                                       std::cos(elevation) * std::sin(azimuth)};
    scene.render.ambient = draw.uniform(0.25, 0.5);
    scene.render.lightIntensity = draw.uniform(0.5, 0.8);
    scene.render.lightAbsorption = scene.render.absorption;
  } else {
    scene.render.ambient = draw.uniform(0.7, 1.0);
  }
}

}  // namespace

Scene randomScene(uint64_t seed, const GridSize& resolution, int frames) {
  Draw draw(seed);
  Scene scene;
  scene.seed = seed;
  scene.resolution = resolution;
  scene.frames = frames;
  const Extent e{static_cast<double>(resolution.x), static_cast<double>(resolution.y),
                 static_cast<double>(resolution.z), static_cast<double>(resolution.x) / 64.0};

  drawSources(draw, e, frames, scene);
  scene.densityBuoyancy = e.scale * draw.uniform(0.035, 0.07);
  if (draw.chance(0.5)) {
    const double temperature = draw.uniform(0.5, 1.0);
    for (Source& source : scene.sources) source.temperature = Keyframes<double>::constant(temperature);
    scene.temperatureBuoyancy = e.scale * draw.uniform(0.015, 0.035);
  }

  // Wind: a horizontal acceleration of the smoke that turns and changes strength at four keyframes.
  const double windMagnitude = scene.densityBuoyancy * draw.uniform(0.0, 0.5);
  double direction = draw.uniform(0, 2 * std::numbers::pi);
  scene.wind.points.clear();
  for (int k = 0; k < 4; ++k) {
    const double strength = windMagnitude * draw.uniform(0.4, 1.0);
    scene.wind.points.emplace_back(frames * k / 3.0, Vec3{strength * std::cos(direction), 0, strength * std::sin(direction)});
    direction += draw.uniform(-1.2, 1.2);
  }
  scene.windWeighting = WindWeighting::Density;
  scene.vorticity = draw.uniform(0.0, 0.15);

  if (draw.chance(0.25)) {
    const Vec3& below = scene.sources.front().shape.centre;
    Obstacle obstacle;
    obstacle.shape.kind = physics::SourceShape::Sphere;
    obstacle.shape.centre = {below[0] + e.nx * draw.uniform(-0.12, 0.12), e.ny * draw.uniform(0.4, 0.6),
                             below[2] + e.nz * draw.uniform(-0.12, 0.12)};
    obstacle.shape.size = {e.nx * draw.uniform(0.08, 0.14), 0, 0};
    scene.obstacles.push_back(obstacle);
  }
  drawRender(draw, e, scene);
  scene.render.width = static_cast<int>(resolution.x);
  scene.render.height = static_cast<int>(resolution.y);
  return scene;
}

}  // namespace smokesvd::sim

// A smoke scene: the domain, its boundaries and obstacles, the inflow sources, the forces, the solver
// settings and the renders, everything `smokesvd simulate` needs to reproduce a run exactly. Scenes are
// JSON files (docs/simulation.md lists every field); lengths are in cells, velocities in cells per
// step, accelerations in cells per step², times in frames.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/physics/advection.h"
#include "pipeline/physics/sources.h"
#include "runtime/geometry.h"

namespace smokesvd::sim {

// Bounds a scene file and the flags of `smokesvd simulate` share: sides from kMinSceneSide to
// kMaxGridSide cells (runtime/geometry.h), 1 to kMaxFrames frames.
inline constexpr int64_t kMinSceneSide = 3;
inline constexpr int kMaxFrames = 1000000;

// A value that may change over time: piecewise linear through (frame, value) points, constant before
// the first and after the last. One point is a constant.
template <typename T>
struct Keyframes {
  std::vector<std::pair<double, T>> points;
  static Keyframes constant(T value) { return {{{0.0, value}}}; }
  T at(double frame) const;
  bool operator==(const Keyframes&) const = default;
};

enum class Boundary { Wall, Open };
enum class WindWeighting { Uniform, Density };

// Geometry shared by obstacles and sources; `size` as in physics::SourceState (radius; half extents;
// radius and half height).
struct Geometry {
  physics::SourceShape kind = physics::SourceShape::Sphere;
  Vec3 centre{0, 0, 0};
  Vec3 size{1, 1, 1};
  Vec3 axis{0, 1, 0};
  bool operator==(const Geometry&) const = default;
};

// Active from frame `first` up to and excluding `last` (-1: to the end).
struct FrameRange {
  int first = 0;
  int last = -1;
  bool contains(int frame) const { return frame >= first && (last < 0 || frame < last); }
  bool operator==(const FrameRange&) const = default;
};

struct Obstacle {
  Geometry shape;
  FrameRange frames;
  bool operator==(const Obstacle&) const = default;
};

struct Noise {
  double amplitude = 0;      // density varies by ± this fraction
  double scale = 4;          // cells between lattice points
  Vec3 velocity{0, 0, 0};    // the noise pattern moves with this velocity (cells per frame)
  uint32_t seed = 0;
  bool operator==(const Noise&) const = default;
};

struct Source {
  Geometry shape;
  physics::InflowMode mode = physics::InflowMode::Set;
  Keyframes<double> density = Keyframes<double>::constant(1.0);
  Keyframes<double> temperature = Keyframes<double>::constant(0.0);
  std::optional<Keyframes<Vec3>> velocity;  // absent: the source does not set the velocity
  Noise noise;
  FrameRange frames;
  bool operator==(const Source&) const = default;
};

struct ForceField {
  std::filesystem::path file;  // .npz or .npy with a cell-centred acceleration [z, y, x, 3]
  std::string key = "force";   // member of an .npz
  double scale = 1;
  FrameRange frames;
  bool operator==(const ForceField&) const = default;
};

struct RenderSpec {
  bool enabled = true;
  int views = 16;              // orbit views evenly on [0°, 180°)
  int width = 0, height = 0;   // pixels
  double step = 1, absorption = 0.3, ambient = 1;
  double exposure = 1;         // PNG value = clamp(exposure · radiance, 0, 1)
  std::optional<Vec3> lightDirection;  // toward the light; absent: no light
  double lightIntensity = 1, lightAbsorption = 1;
  bool operator==(const RenderSpec&) const = default;
};

struct Scene {
  uint64_t seed = 0;                       // the seed a random scene was drawn with (recorded only)
  GridSize resolution;                     // cells along x, y (up), z
  int frames = 1;
  int stepsPerFrame = 1;
  double dt = 1;
  // x low, x high, y low (floor), y high (top), z low, z high. The outer cell layer is wall or open.
  std::array<Boundary, 6> boundaries{Boundary::Wall, Boundary::Wall, Boundary::Wall,
                                     Boundary::Open, Boundary::Wall, Boundary::Wall};
  physics::AdvectionScheme advection = physics::AdvectionScheme::MacCormack;
  double advectionStrength = 1;
  double pressureTolerance = 1e-4;
  int pressureMaxIterations = 100;
  Vec3 gravity{0, -1, 0};
  double densityBuoyancy = 0;              // acceleration per unit density is −gravity · this
  double temperatureBuoyancy = 0;          // acceleration per unit temperature is −gravity · this
  Keyframes<Vec3> wind = Keyframes<Vec3>::constant({0, 0, 0});
  WindWeighting windWeighting = WindWeighting::Density;
  double vorticity = 0;                    // vorticity confinement strength ε
  std::vector<ForceField> forceFields;
  std::vector<Obstacle> obstacles;
  std::vector<Source> sources;
  RenderSpec render;

  bool tracksTemperature() const;  // a source emits heat or temperature drives buoyancy
  bool operator==(const Scene&) const = default;
};

// Parses and checks a scene; `name` (usually the file path) and the field path appear in every error.
// Relative force-field paths are resolved against `baseDirectory`.
Scene parseScene(const nlohmann::json& document, const std::string& name,
                 const std::filesystem::path& baseDirectory = {});
Scene readScene(const std::filesystem::path& path);
nlohmann::json sceneToJson(const Scene& scene);
// Writes scene.json atomically (a temporary name, then renamed).
void writeScene(const std::filesystem::path& path, const Scene& scene);

}  // namespace smokesvd::sim

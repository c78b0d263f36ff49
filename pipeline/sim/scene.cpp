#include "pipeline/sim/scene.h"

#include <fstream>
#include <sstream>

#include "nets/io/file_io.h"
#include "pipeline/sim/json_fields.h"
#include "runtime/error.h"

namespace smokesvd::sim {
namespace {

using nlohmann::json;
using physics::SourceShape;

// Bounds of the physical numbers, far beyond any sensible scene but small enough that float32 kernels
// neither overflow nor lose them (a source of radius 1e30 would add nothing).
constexpr double kMaxLength = 1e5;        // cells: centres, sizes, radii, noise scale
constexpr double kMaxSpeed = 1e4;         // cells per step
constexpr double kMaxAcceleration = 1e4;  // cells per step²: gravity, wind
constexpr double kMaxCoefficient = 1e4;   // buoyancy per unit density or temperature, force-field scale
const char* const kBoundaryNames[6] = {"x_low", "x_high", "y_low", "y_high", "z_low", "z_high"};

double lerp(double a, double b, double t) { return a + (b - a) * t; }
Vec3 lerp(const Vec3& a, const Vec3& b, double t) { return {lerp(a[0], b[0], t), lerp(a[1], b[1], t), lerp(a[2], b[2], t)}; }

// ---- reading ----

template <typename T, typename ReadValue>
Keyframes<T> readKeyframes(const JsonField& field, bool isConstant, ReadValue readValue) {
  if (isConstant) return Keyframes<T>::constant(readValue(field));
  Keyframes<T> result;
  const std::vector<JsonField> items = field.items();
  if (items.empty()) field.fail("a value or a list of [frame, value] keyframes");
  for (const JsonField& item : items) {
    const std::vector<JsonField> pair = item.items();
    if (pair.size() != 2) item.fail("a keyframe [frame, value]");
    const double frame = pair[0].number(-kMaxFrames, kMaxFrames);
    if (!result.points.empty() && frame <= result.points.back().first) pair[0].fail("a frame after the previous keyframe's");
    result.points.emplace_back(frame, readValue(pair[1]));
  }
  return result;
}

Keyframes<double> readScalarKeyframes(const JsonField& field, double low, double high) {
  return readKeyframes<double>(field, field.json().is_number(),
                               [&](const JsonField& f) { return f.number(low, high); });
}

Keyframes<Vec3> readVectorKeyframes(const JsonField& field, double limit) {
  const bool isConstant = field.json().is_array() && !field.json().empty() && field.json()[0].is_number();
  return readKeyframes<Vec3>(field, isConstant, [limit](const JsonField& f) { return f.vec3(limit); });
}

FrameRange readFrameRange(const JsonField& parent) {
  FrameRange range;
  if (std::optional<JsonField> field = parent.find("frames")) {
    const std::vector<JsonField> pair = field->items();
    if (pair.size() != 2) field->fail("[first, last] frames (last -1: to the end)");
    range.first = static_cast<int>(pair[0].integer(0, kMaxFrames));
    range.last = static_cast<int>(pair[1].integer(-1, kMaxFrames));
    if (range.last >= 0 && range.last <= range.first) field->fail("[first, last] with last > first, or last = -1");
  }
  return range;
}

// The geometry members of an obstacle or source object.
Geometry readShape(const JsonField& object) {
  Geometry shape;
  const std::string kind = object.at("shape").oneOf({"sphere", "box", "cylinder"});
  shape.centre = object.at("centre").vec3(kMaxLength);
  if (kind == "sphere") {
    shape.kind = SourceShape::Sphere;
    shape.size = {object.at("radius").positive(kMaxLength), 0, 0};
  } else if (kind == "box") {
    shape.kind = SourceShape::Box;
    shape.size = object.at("half_size").positiveVec3(kMaxLength);
  } else {
    shape.kind = SourceShape::Cylinder;
    shape.size = {object.at("radius").positive(kMaxLength), object.at("half_height").positive(kMaxLength), 0};
    if (std::optional<JsonField> axis = object.find("axis")) {
      shape.axis = axis->vec3(kMaxLength);
      if (shape.axis == Vec3{0, 0, 0}) axis->fail("a non-zero axis");
    }
  }
  return shape;
}

Obstacle readObstacle(const JsonField& object) {
  object.allowOnly({"shape", "centre", "radius", "half_size", "half_height", "axis", "frames"});
  return {readShape(object), readFrameRange(object)};
}

Source readSource(const JsonField& object) {
  object.allowOnly({"shape", "centre", "radius", "half_size", "half_height", "axis", "frames", "mode", "density",
                    "temperature", "velocity", "noise"});
  Source source;
  source.shape = readShape(object);
  source.frames = readFrameRange(object);
  if (std::optional<JsonField> mode = object.find("mode"))
    source.mode = mode->oneOf({"set", "add"}) == "set" ? physics::InflowMode::Set : physics::InflowMode::Add;
  if (std::optional<JsonField> density = object.find("density")) source.density = readScalarKeyframes(*density, 0, 1e6);
  if (std::optional<JsonField> temperature = object.find("temperature"))
    source.temperature = readScalarKeyframes(*temperature, 0, 1e6);
  if (std::optional<JsonField> velocity = object.find("velocity")) source.velocity = readVectorKeyframes(*velocity, kMaxSpeed);
  if (std::optional<JsonField> noise = object.find("noise")) {
    noise->allowOnly({"amplitude", "scale", "velocity", "seed"});
    if (std::optional<JsonField> f = noise->find("amplitude")) source.noise.amplitude = f->number(0, 1);
    if (std::optional<JsonField> f = noise->find("scale")) source.noise.scale = f->positive(kMaxLength);
    if (std::optional<JsonField> f = noise->find("velocity")) source.noise.velocity = f->vec3(kMaxSpeed);
    if (std::optional<JsonField> f = noise->find("seed")) source.noise.seed = static_cast<uint32_t>(f->integer(0, 0xffffff));
  }
  return source;
}

ForceField readForceField(const JsonField& object, const std::filesystem::path& base) {
  object.allowOnly({"file", "key", "scale", "frames"});
  ForceField field;
  const std::string file = object.at("file").string();
  if (file.empty()) object.at("file").fail("a file name");
  field.file = std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : base / file;
  if (std::optional<JsonField> key = object.find("key")) field.key = key->string();
  if (std::optional<JsonField> scale = object.find("scale")) field.scale = scale->number(-kMaxCoefficient, kMaxCoefficient);
  field.frames = readFrameRange(object);
  return field;
}

RenderSpec readRender(const JsonField& object) {
  object.allowOnly({"enabled", "views", "width", "height", "step", "absorption", "ambient", "exposure", "light"});
  RenderSpec render;
  if (std::optional<JsonField> f = object.find("enabled")) render.enabled = f->boolean();
  if (std::optional<JsonField> f = object.find("views")) render.views = static_cast<int>(f->integer(1, 360));
  if (std::optional<JsonField> f = object.find("width")) render.width = static_cast<int>(f->integer(1, 8192));
  if (std::optional<JsonField> f = object.find("height")) render.height = static_cast<int>(f->integer(1, 8192));
  if (std::optional<JsonField> f = object.find("step")) render.step = f->number(0.01, 100);
  if (std::optional<JsonField> f = object.find("absorption")) render.absorption = f->number(0, 1e6);
  if (std::optional<JsonField> f = object.find("ambient")) render.ambient = f->number(0, 1e6);
  if (std::optional<JsonField> f = object.find("exposure")) render.exposure = f->positive(1e6);
  if (std::optional<JsonField> light = object.find("light")) {
    light->allowOnly({"direction", "intensity", "absorption"});
    render.lightDirection = light->at("direction").vec3(kMaxLength);
    if (*render.lightDirection == Vec3{0, 0, 0}) light->at("direction").fail("a non-zero direction");
    if (std::optional<JsonField> f = light->find("intensity")) render.lightIntensity = f->number(0, 1e6);
    if (std::optional<JsonField> f = light->find("absorption")) render.lightAbsorption = f->number(0, 1e6);
  }
  return render;
}

// ---- writing ----

json toJson(const Vec3& v) { return json::array({v[0], v[1], v[2]}); }

json toJson(double v) { return json(v); }

template <typename T>
json toJson(const Keyframes<T>& k) {
  if (k.points.size() == 1) return toJson(k.points[0].second);
  json list = json::array();
  for (const auto& [frame, value] : k.points) list.push_back(json::array({frame, toJson(value)}));
  return list;
}

void writeShape(json& object, const Geometry& shape) {
  static const char* const kinds[] = {"sphere", "box", "cylinder"};
  object["shape"] = kinds[static_cast<int>(shape.kind)];
  object["centre"] = toJson(shape.centre);
  if (shape.kind == SourceShape::Sphere) {
    object["radius"] = shape.size[0];
  } else if (shape.kind == SourceShape::Box) {
    object["half_size"] = toJson(shape.size);
  } else {
    object["radius"] = shape.size[0];
    object["half_height"] = shape.size[1];
    object["axis"] = toJson(shape.axis);
  }
}

json toJson(const FrameRange& range) { return json::array({range.first, range.last}); }

}  // namespace

template <typename T>
T Keyframes<T>::at(double frame) const {
  if (points.empty()) throw Error("keyframes: no points");
  if (frame <= points.front().first) return points.front().second;
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (frame <= points[i].first) {
      const double t = (frame - points[i - 1].first) / (points[i].first - points[i - 1].first);
      return lerp(points[i - 1].second, points[i].second, t);
    }
  }
  return points.back().second;
}
template struct Keyframes<double>;
template struct Keyframes<Vec3>;

bool Scene::tracksTemperature() const {
  if (temperatureBuoyancy != 0) return true;
  for (const Source& source : sources)
    for (const auto& point : source.temperature.points)
      if (point.second != 0) return true;
  return false;
}

Scene parseScene(const json& document, const std::string& name, const std::filesystem::path& baseDirectory) {
  const JsonField root(document, name);
  root.allowOnly({"seed", "resolution", "frames", "steps_per_frame", "dt", "boundaries", "advection", "pressure",
                  "gravity", "buoyancy", "wind", "vorticity", "force_fields", "obstacles", "sources", "render"});
  Scene scene;
  if (std::optional<JsonField> f = root.find("seed")) scene.seed = static_cast<uint64_t>(f->integer(0, INT64_MAX));
  {
    const JsonField resolution = root.at("resolution");
    const std::vector<JsonField> sides = resolution.items();
    if (sides.size() != 3) resolution.fail("three cell counts [x, y, z]");
    scene.resolution = {.x = sides[0].integer(kMinSceneSide, kMaxGridSide),
                        .y = sides[1].integer(kMinSceneSide, kMaxGridSide),
                        .z = sides[2].integer(kMinSceneSide, kMaxGridSide)};
    checkGridSize(scene.resolution, name + ": field 'resolution'");
  }
  scene.frames = static_cast<int>(root.at("frames").integer(1, kMaxFrames));
  if (std::optional<JsonField> f = root.find("steps_per_frame")) scene.stepsPerFrame = static_cast<int>(f->integer(1, 1000));
  if (std::optional<JsonField> f = root.find("dt")) scene.dt = f->positive(1e3);
  if (std::optional<JsonField> boundaries = root.find("boundaries")) {
    boundaries->allowOnly({"x_low", "x_high", "y_low", "y_high", "z_low", "z_high"});
    for (int side = 0; side < 6; ++side)
      if (std::optional<JsonField> f = boundaries->find(kBoundaryNames[side]))
        scene.boundaries[side] = f->oneOf({"wall", "open"}) == "wall" ? Boundary::Wall : Boundary::Open;
  }
  if (std::optional<JsonField> advection = root.find("advection")) {
    advection->allowOnly({"scheme", "strength"});
    if (std::optional<JsonField> f = advection->find("scheme"))
      scene.advection = f->oneOf({"semi-lagrangian", "maccormack"}) == "maccormack"
                            ? physics::AdvectionScheme::MacCormack
                            : physics::AdvectionScheme::SemiLagrangian;
    if (std::optional<JsonField> f = advection->find("strength")) scene.advectionStrength = f->number(0, 1);
  }
  if (std::optional<JsonField> pressure = root.find("pressure")) {
    pressure->allowOnly({"tolerance", "max_iterations"});
    if (std::optional<JsonField> f = pressure->find("tolerance")) scene.pressureTolerance = f->number(1e-7, 0.5);
    if (std::optional<JsonField> f = pressure->find("max_iterations"))
      scene.pressureMaxIterations = static_cast<int>(f->integer(1, 10000));
  }
  if (std::optional<JsonField> f = root.find("gravity")) scene.gravity = f->vec3(kMaxAcceleration);
  if (std::optional<JsonField> buoyancy = root.find("buoyancy")) {
    buoyancy->allowOnly({"density", "temperature"});
    if (std::optional<JsonField> f = buoyancy->find("density"))
      scene.densityBuoyancy = f->number(-kMaxCoefficient, kMaxCoefficient);
    if (std::optional<JsonField> f = buoyancy->find("temperature"))
      scene.temperatureBuoyancy = f->number(-kMaxCoefficient, kMaxCoefficient);
  }
  if (std::optional<JsonField> wind = root.find("wind")) {
    wind->allowOnly({"acceleration", "weighting"});
    scene.wind = readVectorKeyframes(wind->at("acceleration"), kMaxAcceleration);
    if (std::optional<JsonField> f = wind->find("weighting"))
      scene.windWeighting = f->oneOf({"density", "uniform"}) == "density" ? WindWeighting::Density : WindWeighting::Uniform;
  }
  if (std::optional<JsonField> f = root.find("vorticity")) scene.vorticity = f->number(0, 1e3);
  if (std::optional<JsonField> list = root.find("force_fields"))
    for (const JsonField& item : list->items()) scene.forceFields.push_back(readForceField(item, baseDirectory));
  if (std::optional<JsonField> list = root.find("obstacles"))
    for (const JsonField& item : list->items()) scene.obstacles.push_back(readObstacle(item));
  if (std::optional<JsonField> list = root.find("sources"))
    for (const JsonField& item : list->items()) scene.sources.push_back(readSource(item));
  if (std::optional<JsonField> render = root.find("render")) scene.render = readRender(*render);
  if (scene.render.width == 0) scene.render.width = static_cast<int>(scene.resolution.x);
  if (scene.render.height == 0) scene.render.height = static_cast<int>(scene.resolution.y);
  return scene;
}

Scene readScene(const std::filesystem::path& path) {
  json document;
  try {
    document = json::parse(io::readTextFile(path));
  } catch (const json::exception& error) {  // syntax, or a number beyond double
    throw Error(path.string() + ": not valid JSON (" + error.what() + ")");
  }
  return parseScene(document, path.string(), std::filesystem::absolute(path).parent_path());
}

json sceneToJson(const Scene& scene) {
  json root;
  root["seed"] = scene.seed;
  root["resolution"] = json::array({scene.resolution.x, scene.resolution.y, scene.resolution.z});
  root["frames"] = scene.frames;
  root["steps_per_frame"] = scene.stepsPerFrame;
  root["dt"] = scene.dt;
  json boundaries;
  for (int side = 0; side < 6; ++side) boundaries[kBoundaryNames[side]] = scene.boundaries[side] == Boundary::Wall ? "wall" : "open";
  root["boundaries"] = boundaries;
  root["advection"] = {{"scheme", scene.advection == physics::AdvectionScheme::MacCormack ? "maccormack" : "semi-lagrangian"},
                       {"strength", scene.advectionStrength}};
  root["pressure"] = {{"tolerance", scene.pressureTolerance}, {"max_iterations", scene.pressureMaxIterations}};
  root["gravity"] = toJson(scene.gravity);
  root["buoyancy"] = {{"density", scene.densityBuoyancy}, {"temperature", scene.temperatureBuoyancy}};
  root["wind"] = {{"acceleration", toJson(scene.wind)},
                  {"weighting", scene.windWeighting == WindWeighting::Density ? "density" : "uniform"}};
  root["vorticity"] = scene.vorticity;
  json fields = json::array();
  for (const ForceField& f : scene.forceFields)
    fields.push_back({{"file", f.file.string()}, {"key", f.key}, {"scale", f.scale}, {"frames", toJson(f.frames)}});
  root["force_fields"] = fields;
  json obstacles = json::array();
  for (const Obstacle& o : scene.obstacles) {
    json object;
    writeShape(object, o.shape);
    object["frames"] = toJson(o.frames);
    obstacles.push_back(object);
  }
  root["obstacles"] = obstacles;
  json sources = json::array();
  for (const Source& s : scene.sources) {
    json object;
    writeShape(object, s.shape);
    object["frames"] = toJson(s.frames);
    object["mode"] = s.mode == physics::InflowMode::Set ? "set" : "add";
    object["density"] = toJson(s.density);
    object["temperature"] = toJson(s.temperature);
    if (s.velocity) object["velocity"] = toJson(*s.velocity);
    object["noise"] = {{"amplitude", s.noise.amplitude}, {"scale", s.noise.scale},
                       {"velocity", toJson(s.noise.velocity)}, {"seed", s.noise.seed}};
    sources.push_back(object);
  }
  root["sources"] = sources;
  const RenderSpec& r = scene.render;
  json render = {{"enabled", r.enabled}, {"views", r.views}, {"width", r.width}, {"height", r.height},
                 {"step", r.step}, {"absorption", r.absorption}, {"ambient", r.ambient}, {"exposure", r.exposure}};
  if (r.lightDirection)
    render["light"] = {{"direction", toJson(*r.lightDirection)}, {"intensity", r.lightIntensity},
                       {"absorption", r.lightAbsorption}};
  root["render"] = render;
  return root;
}

void writeScene(const std::filesystem::path& path, const Scene& scene) {
  io::writeAtomically(path, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary);
    if (!out) throw Error(temporary.string() + ": cannot write the scene file");
    out << sceneToJson(scene).dump(2) << "\n";
    if (!out) throw Error(temporary.string() + ": writing the scene file failed");
  });
}

}  // namespace smokesvd::sim

#include "pipeline/physics/forces.h"

#include <string>

#include "runtime/error.h"

namespace smokesvd::physics {
namespace {

constexpr std::array<uint32_t, 3> kCellWorkgroup{8, 4, 4};

struct GridPush {
  int32_t x, y, z;
};
GridPush push(const GridSize& grid) {
  return {static_cast<int32_t>(grid.x), static_cast<int32_t>(grid.y), static_cast<int32_t>(grid.z)};
}

template <typename Push>
void dispatchCells(Stream& stream, const char* name, std::initializer_list<Arg> args, const Push& push,
                   const GridSize& grid, std::vector<int32_t> constants = {}) {
  auto groups = [](int64_t n, uint32_t size) { return static_cast<uint32_t>((n + size - 1) / size); };
  stream.dispatch(stream.kernel(std::string("physics/") + name, kCellWorkgroup, std::move(constants)), args, push,
                  {groups(grid.x, kCellWorkgroup[0]), groups(grid.y, kCellWorkgroup[1]),
                   groups(grid.z, kCellWorkgroup[2])});
}

// Grids whose width is a multiple of 4 run the block variants of the kernels (four cells per invocation,
// vec4 texels; shaders/physics/force_blocks.glsl).
bool aligned(const GridSize& grid) { return grid.x % 4 == 0; }
GridPush blocks(const GridSize& grid) { return {static_cast<int32_t>(grid.x / 4), static_cast<int32_t>(grid.y), static_cast<int32_t>(grid.z)}; }

template <typename Push>
void dispatchBlocks(Stream& stream, const char* name, std::initializer_list<Arg> args, const Push& push,
                    const GridSize& grid, std::vector<int32_t> constants = {}) {
  auto groups = [](int64_t n, uint32_t size) { return static_cast<uint32_t>((n + size - 1) / size); };
  stream.dispatch(stream.kernel(std::string("physics/") + name, kCellWorkgroup, std::move(constants)), args, push,
                  {groups(grid.x / 4, kCellWorkgroup[0]), groups(grid.y, kCellWorkgroup[1]),
                   groups(grid.z, kCellWorkgroup[2])});
}

// The grid of `flags`, after checking that velocity and out are MAC fields of it and distinct.
GridSize checkedGrid(const Tensor& flags, const Tensor& velocity, const Tensor& out, const char* what) {
  const GridSize grid = volumeGrid(flags, what);
  requireVector(velocity, grid, what);
  requireVector(out, grid, what);
  if (velocity.sharedBuffer() == out.sharedBuffer())
    throw Error(std::string(what) + ": the output velocity must not alias the input");
  return grid;
}

}  // namespace

void addBuoyancy(Stream& stream, const Tensor& flags, const Tensor& density, const Tensor* temperature,
                 const Tensor& velocity, const Buoyancy& buoyancy, float dt, const Tensor& out) {
  const GridSize grid = checkedGrid(flags, velocity, out, "buoyancy");
  requireVolume(density, grid, "buoyancy (density)");
  if (temperature) requireVolume(*temperature, grid, "buoyancy (temperature)");
  auto vec4 = [](const glm::vec3& v) { return std::array<float, 4>{v.x, v.y, v.z, 0.0f}; };
  const glm::vec3 perTemperature = temperature ? buoyancy.perTemperature : glm::vec3{0, 0, 0};
  struct {
    GridPush size;
    float dt;
    std::array<float, 4> uniform, perDensity, perTemperature;
  } p{aligned(grid) ? blocks(grid) : push(grid), dt, vec4(buoyancy.uniform), vec4(buoyancy.perDensity),
      vec4(perTemperature)};
  const Tensor& heat = temperature ? *temperature : density;
  if (aligned(grid))
    dispatchBlocks(stream, "buoyancy_blocks", {asVec4(flags), asVec4(density), asVec4(heat), asVec4(velocity), out}, p,
                   grid, {temperature ? 1 : 0});
  else
    dispatchCells(stream, "buoyancy", {flags, density, heat, velocity, out}, p, grid, {temperature ? 1 : 0});
}

void addForceField(Stream& stream, const Tensor& flags, const Tensor& force, const Tensor& velocity, float dt,
                   const Tensor& out) {
  const GridSize grid = checkedGrid(flags, velocity, out, "force field");
  requireVector(force, grid, "force field (force)");
  struct {
    GridPush size;
    float dt;
  } p{aligned(grid) ? blocks(grid) : push(grid), dt};
  if (aligned(grid))
    dispatchBlocks(stream, "force_field_blocks", {asVec4(flags), asVec4(force), asVec4(velocity), out}, p, grid);
  else
    dispatchCells(stream, "force_field", {flags, force, velocity, out}, p, grid);
}

void vorticityField(Stream& stream, const Tensor& velocity, const Tensor& vorticity) {
  const GridSize grid = vectorGrid(velocity, "vorticity (velocity)");
  if (vorticity.shape() != Shape{4, grid.z, grid.y, grid.x})
    throw Error("vorticity: expected the output [4, " + std::to_string(grid.z) + ", " + std::to_string(grid.y) + ", " +
                std::to_string(grid.x) + "], got " + toString(vorticity.shape()));
  if (aligned(grid))
    dispatchBlocks(stream, "vorticity_field_blocks", {asVec4(velocity), vorticity}, blocks(grid), grid);
  else
    dispatchCells(stream, "vorticity_field", {velocity, vorticity}, push(grid), grid);
}

void vorticityForce(Stream& stream, const Tensor& vorticity, float strength, const Tensor& force) {
  const GridSize grid = vectorGrid(force, "vorticity force (force)");
  if (vorticity.shape() != Shape{4, grid.z, grid.y, grid.x})
    throw Error("vorticity force: expected a vorticity field [4, D, H, W] of the grid, got " + toString(vorticity.shape()));
  struct {
    GridPush size;
    float strength;
  } p{aligned(grid) ? blocks(grid) : push(grid), strength};
  if (aligned(grid))
    dispatchBlocks(stream, "vorticity_force_blocks", {asVec4(vorticity), force}, p, grid);
  else
    dispatchCells(stream, "vorticity_force", {vorticity, force}, p, grid);
}

void addVorticityConfinement(Stream& stream, const Tensor& flags, const Tensor& vorticity, const Tensor& velocity,
                             float strength, float dt, const Tensor& out) {
  const GridSize grid = checkedGrid(flags, velocity, out, "vorticity confinement");
  const Tensor force(stream.context(), grid.vector());
  vorticityForce(stream, vorticity, strength, force);
  addForceField(stream, flags, force, velocity, dt, out);
}

}  // namespace smokesvd::physics

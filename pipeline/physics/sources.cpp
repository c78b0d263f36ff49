#include "pipeline/physics/sources.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "nets/ops/elementwise.h"
#include "runtime/error.h"

namespace smokesvd::physics {
namespace {

constexpr int kTexelsPerSource = 6;  // shaders/physics/inflow_sources.glsl
constexpr int kFloatsPerSource = 4 * kTexelsPerSource;
constexpr std::array<uint32_t, 3> kCellWorkgroup{8, 4, 4};

struct GridPush {
  int32_t x, y, z;
};
GridPush push(const GridSize& grid) {
  return {static_cast<int32_t>(grid.x), static_cast<int32_t>(grid.y), static_cast<int32_t>(grid.z)};
}

// The part of `box` inside the grid, as a low corner and an extent (empty extent: nothing to do).
struct Region {
  std::array<int32_t, 3> low{0, 0, 0};
  std::array<int64_t, 3> extent{0, 0, 0};
  bool empty() const { return extent[0] <= 0 || extent[1] <= 0 || extent[2] <= 0; }
};
Region clip(const CellBox& box, const GridSize& grid) {
  const int64_t sides[3] = {grid.x, grid.y, grid.z};
  Region region;
  for (int a = 0; a < 3; ++a) {
    const int64_t low = std::clamp<int64_t>(box.low[a], 0, sides[a]);
    const int64_t high = std::clamp<int64_t>(box.high[a], 0, sides[a]);
    region.low[a] = static_cast<int32_t>(low);
    region.extent[a] = high - low;
  }
  return region;
}

// Runs `name` with one invocation per cell of `region`.
template <typename Push>
void dispatchRegion(Stream& stream, const char* name, std::initializer_list<Arg> args, const Push& push,
                    const Region& region) {
  auto groups = [](int64_t n, uint32_t size) { return static_cast<uint32_t>((n + size - 1) / size); };
  stream.dispatch(stream.kernel(std::string("physics/") + name, kCellWorkgroup), args, push,
                  {groups(region.extent[0], kCellWorkgroup[0]), groups(region.extent[1], kCellWorkgroup[1]),
                   groups(region.extent[2], kCellWorkgroup[2])});
}

// The cells a source may cover: its bounding sphere plus the one-cell ramp of the coverage.
CellBox boundingBox(const SourceState& s) {
  float radius = s.size[0];
  if (s.shape == SourceShape::Box) radius = std::sqrt(s.size[0] * s.size[0] + s.size[1] * s.size[1] + s.size[2] * s.size[2]);
  if (s.shape == SourceShape::Cylinder) radius = std::sqrt(s.size[0] * s.size[0] + s.size[1] * s.size[1]);
  CellBox box;
  for (int a = 0; a < 3; ++a) {
    box.low[a] = static_cast<int32_t>(std::floor(s.centre[a] - radius - 1.0f));
    box.high[a] = static_cast<int32_t>(std::ceil(s.centre[a] + radius + 1.0f));
  }
  return box;
}

CellBox unite(const CellBox& a, const CellBox& b) {
  if (a.low == a.high) return b;
  CellBox box;
  for (int i = 0; i < 3; ++i) {
    box.low[i] = std::min(a.low[i], b.low[i]);
    box.high[i] = std::max(a.high[i], b.high[i]);
  }
  return box;
}

glm::vec3 normalised(const glm::vec3& v) {
  const float length = glm::length(v);
  if (length <= 0) throw Error("inflow source: a cylinder axis must not be zero");
  return v / length;
}

}  // namespace

SourceTable::SourceTable(Context& context, int capacity)
    : table_(context, {std::max(capacity, 1) * kFloatsPerSource}), capacity_(std::max(capacity, 1)) {
  write({});
}

void SourceTable::write(std::span<const SourceState> states) {
  if (static_cast<int>(states.size()) > capacity_)
    throw Error("inflow sources: " + std::to_string(states.size()) + " sources, the table holds " +
                std::to_string(capacity_));
  std::vector<float> values(static_cast<std::size_t>(capacity_ * kFloatsPerSource), 0.0f);
  for (std::size_t s = 0; s < states.size(); ++s) {
    const SourceState& state = states[s];
    const glm::vec3 axis = state.shape == SourceShape::Cylinder ? normalised(state.axis) : state.axis;
    const float rows[kTexelsPerSource][4] = {
        {state.centre[0], state.centre[1], state.centre[2], static_cast<float>(state.shape)},
        {state.size[0], state.size[1], state.size[2], static_cast<float>(state.mode)},
        {axis[0], axis[1], axis[2], state.density},
        {state.velocity[0], state.velocity[1], state.velocity[2], state.setsVelocity ? 1.0f : 0.0f},
        {state.temperature, state.noiseAmplitude, state.noiseScale, static_cast<float>(state.noiseSeed & 0xffffffu)},
        {state.noiseOffset[0], state.noiseOffset[1], state.noiseOffset[2], 0.0f},
    };
    for (int t = 0; t < kTexelsPerSource; ++t)
      for (int c = 0; c < 4; ++c) values[s * kFloatsPerSource + t * 4 + c] = rows[t][c];
  }
  table_.upload(values);
  count_ = static_cast<int>(states.size());
  coverage_ = velocityCoverage_ = CellBox{};
  for (const SourceState& state : states) {
    coverage_ = unite(coverage_, boundingBox(state));
    if (state.setsVelocity) velocityCoverage_ = unite(velocityCoverage_, boundingBox(state));
  }
}

void inflowFields(Stream& stream, const Tensor& flags, const Tensor& density, const Tensor* temperature,
                  const SourceTable& sources, float dt, const Tensor& densityInflow, const Tensor* temperatureInflow) {
  const GridSize grid = volumeGrid(flags, "inflow (flags)");
  requireVolume(density, grid, "inflow (density)");
  requireVolume(densityInflow, grid, "inflow (density inflow)");
  if ((temperature == nullptr) != (temperatureInflow == nullptr))
    throw Error("inflow: give both the temperature and its inflow, or neither");
  if (temperature) {
    requireVolume(*temperature, grid, "inflow (temperature)");
    requireVolume(*temperatureInflow, grid, "inflow (temperature inflow)");
  }
  // Without a temperature field the kernel reads the density and writes its temperature inflow into a
  // scratch volume nobody reads.
  const Tensor scratch = temperature ? Tensor() : Tensor(stream.context(), grid.volume());
  const Tensor& temperatureOut = temperatureInflow ? *temperatureInflow : scratch;
  ops::fill(stream, densityInflow, 0.0f);
  ops::fill(stream, temperatureOut, 0.0f);
  const Region region = clip(sources.coverage(), grid);
  if (region.empty()) return;
  struct {
    GridPush size;
    int32_t sources;
    std::array<int32_t, 3> low;
    float dt;
  } p{push(grid), sources.count(), region.low, dt};
  dispatchRegion(stream, "inflow_density",
                 {flags, density, temperature ? *temperature : density, asVec4(sources.table()), densityInflow,
                  temperatureOut},
                 p, region);
}

void applySourceVelocity(Stream& stream, const Tensor& flags, const SourceTable& sources, const Tensor& velocity) {
  const GridSize grid = volumeGrid(flags, "source velocity (flags)");
  requireVector(velocity, grid, "source velocity (velocity)");
  const Region region = clip(sources.velocityCoverage(), grid);
  if (region.empty()) return;
  struct {
    GridPush size;
    int32_t sources;
    std::array<int32_t, 3> low;
  } p{push(grid), sources.count(), region.low};
  dispatchRegion(stream, "inflow_velocity", {flags, asVec4(sources.table()), velocity}, p, region);
}

}  // namespace smokesvd::physics

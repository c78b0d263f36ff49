#include "pipeline/sim/outputs.h"

#include <cstdio>

#include "nets/io/finite_values.h"
#include "nets/io/npy.h"
#include "pipeline/physics/grid.h"
#include "runtime/error.h"

namespace smokesvd::sim {
namespace {

namespace fs = std::filesystem;

io::NpyArray volumeArray(const GridSize& grid, std::vector<float> values) {
  return io::NpyArray::fromFloats({grid.z, grid.y, grid.x}, std::move(values));
}

// Planar [3, D, H, W] host values to the file layout [D, H, W, 3].
io::NpyArray vectorArray(const GridSize& grid, const std::vector<float>& planar) {
  const std::size_t cells = static_cast<std::size_t>(grid.cells());
  std::vector<float> interleaved(3 * cells);
  for (std::size_t c = 0; c < cells; ++c)
    for (std::size_t a = 0; a < 3; ++a) interleaved[3 * c + a] = planar[a * cells + c];
  return io::NpyArray::fromFloats({grid.z, grid.y, grid.x, 3}, std::move(interleaved));
}

std::vector<float> planarFrom(const io::NpyArray& array) {
  const std::vector<float> interleaved = array.toFloat();
  const std::size_t cells = interleaved.size() / 3;
  std::vector<float> planar(interleaved.size());
  for (std::size_t c = 0; c < cells; ++c)
    for (std::size_t a = 0; a < 3; ++a) planar[a * cells + c] = interleaved[3 * c + a];
  return planar;
}

}  // namespace

std::string frameName(int frame) {
  char name[16];
  std::snprintf(name, sizeof name, "%04d", frame);
  return name;
}

void writeFields(const fs::path& directory, int frame, const GridSize& grid, const std::vector<float>& density,
                 const std::vector<float>& velocity, const std::vector<float>& inflow) {
  const std::string name = frameName(frame);
  const fs::path fields = directory / "fields";
  fs::create_directories(fields);
  io::writeNpz(fields / ("density_" + name + ".npz"), {{"density", volumeArray(grid, density)}});
  io::writeNpz(fields / ("velocity_" + name + ".npz"), {{"velocity", vectorArray(grid, velocity)}});
  io::writeNpz(fields / ("inflow_" + name + ".npz"), {{"inflow", volumeArray(grid, inflow)}});
}

namespace {

// A field of the frame just simulated, which must be finite: a NaN or infinity stops the run, naming the
// frame, the field and the first bad element, before anything of the frame is written.
io::NpyArray checkedField(const io::NpyArray& array, const Simulator& simulator, const std::string& field) {
  io::requireFiniteValues(array.floats, array.shape, "frame " + std::to_string(simulator.frame() - 1) + ": " + field,
                          std::string("the state (") + kBlownUp + ")");
  return array;
}

}  // namespace

void writeFrameFields(RunFiles& files, const Simulator& simulator) {
  const GridSize& grid = simulator.grid();
  const std::string frame = frameName(simulator.frame() - 1);
  std::map<std::string, io::NpyArray> arrays;
  arrays["density"] = checkedField(volumeArray(grid, simulator.density().download()), simulator, "density");
  arrays["velocity"] = checkedField(vectorArray(grid, simulator.velocity().download()), simulator, "velocity");
  arrays["inflow"] = checkedField(volumeArray(grid, simulator.inflow().download()), simulator, "inflow");
  if (const Tensor* temperature = simulator.temperature())
    arrays["temperature"] = checkedField(volumeArray(grid, temperature->download()), simulator, "temperature");
  fs::create_directories(files.directory() / "fields");
  for (const auto& [name, array] : arrays) io::writeNpz(files.add("fields/" + name + "_" + frame + ".npz"), {{name, array}});
}

void writeFlags(RunFiles& files, const Simulator& simulator) {
  const std::vector<float> flags = simulator.flags().download();
  const GridSize& grid = simulator.grid();
  io::writeNpz(files.add("flags.npz"),
               {{"flags", io::NpyArray::fromInts({grid.z, grid.y, grid.x}, std::vector<int32_t>(flags.begin(), flags.end()))}});
}

void writeCheckpoint(RunFiles& files, const Simulator& simulator) {
  const SimulatorState state = simulator.state();
  const GridSize& grid = simulator.grid();
  std::map<std::string, io::NpyArray> arrays = {
      {"frame", io::NpyArray::fromInts({1}, {state.frame})},
      {"density", volumeArray(grid, state.density)},
      {"velocity", vectorArray(grid, state.velocity)},
      {"pressure", volumeArray(grid, state.pressure)},
  };
  if (!state.temperature.empty()) arrays.emplace("temperature", volumeArray(grid, state.temperature));
  io::writeNpz(files.add("checkpoint.npz"), arrays, false);
}

namespace {

SimulatorState parseCheckpoint(const fs::path& path, const Scene& scene) {
  const std::map<std::string, io::NpyArray> arrays = io::readNpz(path);
  auto member = [&](const char* key) -> const io::NpyArray& {
    auto it = arrays.find(key);
    if (it == arrays.end()) throw Error(path.string() + ": the checkpoint has no '" + key + "' array");
    return it->second;
  };
  const GridSize& grid = scene.resolution;
  const Shape volume = grid.volume(), vector{grid.z, grid.y, grid.x, 3};
  for (const char* key : {"density", "pressure"})
    if (member(key).shape != volume)
      throw Error(path.string() + ": '" + key + "' is " + toString(member(key).shape) + ", the scene needs " + toString(volume));
  if (member("velocity").shape != vector)
    throw Error(path.string() + ": 'velocity' is " + toString(member("velocity").shape) + ", the scene needs " + toString(vector));
  SimulatorState state;
  const std::vector<float> frame = member("frame").toFloat();
  if (frame.size() != 1 || frame[0] < 0 || frame[0] > static_cast<float>(scene.frames))
    throw Error(path.string() + ": 'frame' must hold one frame count in [0, " + std::to_string(scene.frames) + "]");
  state.frame = static_cast<int>(frame[0]);
  state.density = member("density").toFloat();
  state.pressure = member("pressure").toFloat();
  state.velocity = planarFrom(member("velocity"));
  if (scene.tracksTemperature()) state.temperature = member("temperature").toFloat();
  for (const auto& [name, values] : {std::pair{"density", &state.density}, {"velocity", &state.velocity},
                                     {"pressure", &state.pressure}, {"temperature", &state.temperature}})
    io::requireFiniteValues(*values, {static_cast<int64_t>(values->size())}, path.string() + ": '" + name + "'",
                            "a checkpoint's state");
  return state;
}

}  // namespace

std::optional<SimulatorState> readCheckpoint(const fs::path& directory, const Scene& scene) {
  const fs::path path = directory / "checkpoint.npz";
  if (!fs::exists(path)) return std::nullopt;
  try {
    return parseCheckpoint(path, scene);
  } catch (const Error& error) {
    throw Error(std::string(error.what()) + " -- the checkpoint is unusable: delete " + path.string() +
                " to simulate the scene again from its first frame, or run with --overwrite");
  }
}

}  // namespace smokesvd::sim

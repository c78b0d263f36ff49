#include "pipeline/media/volume_file.h"

#include <map>

#include "nets/io/finite_values.h"
#include "nets/io/npy.h"
#include "runtime/error.h"

namespace smokesvd::media {
namespace {

std::string chooseKey(const std::map<std::string, io::NpyArray>& arrays, const std::string& key,
                      const std::string& file) {
  std::string keys;
  for (const auto& [name, array] : arrays) keys += (keys.empty() ? "" : ", ") + name;
  if (!key.empty()) {
    if (!arrays.contains(key)) throw Error(file + ": no array '" + key + "'; the file holds: " + keys);
    return key;
  }
  for (const char* preferred : {"density", "data", "arr_0"})
    if (arrays.contains(preferred)) return preferred;
  if (arrays.size() == 1) return arrays.begin()->first;
  throw Error(file + ": cannot tell which array is the density (none of density, data, arr_0); it holds: " + keys +
              "; choose one with --key");
}

}  // namespace

DensityVolume readDensityVolume(const std::filesystem::path& path, const std::string& key) {
  const std::string file = path.string();
  io::NpyArray array;
  std::string source = file;
  if (path.extension() == ".npz") {
    const std::map<std::string, io::NpyArray> arrays = io::readNpz(path);
    const std::string chosen = chooseKey(arrays, key, file);
    array = arrays.at(chosen);
    source += ":" + chosen;
  } else if (path.extension() == ".npy") {
    array = io::readNpy(path);
  } else {
    throw Error(file + ": expected a .npy or .npz volume");
  }
  Shape shape = array.shape;
  if (shape.size() == 4 && shape[3] == 3)
    throw Error(source + ": shape " + toString(shape) + " is a velocity field [z, y, x, 3], not a density");
  if (shape.size() == 4 && shape[3] == 1) shape.pop_back();
  while (shape.size() > 3 && shape.front() == 1) shape.erase(shape.begin());
  if (shape.size() != 3 || numElements(shape) == 0)
    throw Error(source + ": shape " + toString(array.shape) +
                " is not a density volume; expected [z, y, x], [z, y, x, 1] or [1, 1, z, y, x]");
  const GridSize grid{.x = shape[2], .y = shape[1], .z = shape[0]};
  checkGridSize(grid, source);
  std::vector<float> values = array.toFloat();
  io::requireFiniteValues(values, array.shape, source, "densities");
  return {grid, std::move(values)};
}

}  // namespace smokesvd::media

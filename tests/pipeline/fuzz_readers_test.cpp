// Seeded random mutations of valid files, fed to their readers: .npy, .npz, .safetensors, scene.json
// and a calibration info.json. Every case must end in a correct read (the reader's result survives a
// round trip through its writer) or a smokesvd::Error -- never another exception, a crash or a hang --
// and in bounded time.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>

#include "nets/io/file_io.h"
#include "nets/io/npy.h"
#include "nets/io/safetensors.h"
#include "nets/io/temporary_folder.h"
#include "pipeline/camera/calibration.h"
#include "pipeline/sim/scene.h"
#include "runtime/error.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::byte>;

constexpr int kCasesPerFormat = 5000;
constexpr double kSecondsPerCase = 2.0;

// Text tokens a mutation may splice into a file: extremes, wrong types and syntax.
const char* const kTokens[] = {"-1", "0", "1e30", "-1e308", "1e400", "NaN", "nan", "Infinity", "18446744073709551616",
                               "9223372036854775807", "-16", "null", "true", "\"x\"", "[]", "{}", "[[[[[[[[", "]]]",
                               "(", ")", ",", ":", "'", "\"", "\\u0000", "\x93NUMPY", "PK\x03\x04", "\xff\xfe"};

class Mutator {
 public:
  explicit Mutator(uint64_t seed) : random_(seed) {}

  Bytes mutate(Bytes bytes) {
    const int edits = 1 + below(4);
    for (int e = 0; e < edits; ++e) edit(bytes);
    return bytes;
  }

 private:
  int below(std::size_t n) { return n == 0 ? 0 : static_cast<int>(random_() % n); }
  std::size_t position(const Bytes& bytes) { return static_cast<std::size_t>(below(bytes.size() + 1)); }

  void edit(Bytes& bytes) {
    switch (below(8)) {
      case 0:  // flip one bit
        if (!bytes.empty()) bytes[position(bytes) % bytes.size()] ^= std::byte{static_cast<unsigned char>(1u << below(8))};
        break;
      case 1:  // a random byte
        if (!bytes.empty()) bytes[position(bytes) % bytes.size()] = std::byte{static_cast<unsigned char>(below(256))};
        break;
      case 2: {  // insert random bytes
        const std::size_t at = position(bytes);
        Bytes inserted(static_cast<std::size_t>(1 + below(16)));
        for (std::byte& b : inserted) b = std::byte{static_cast<unsigned char>(below(256))};
        bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(at), inserted.begin(), inserted.end());
        break;
      }
      case 3: {  // delete a range
        const std::size_t at = position(bytes), count = std::min<std::size_t>(static_cast<std::size_t>(1 + below(64)), bytes.size() - std::min(at, bytes.size()));
        bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(at), bytes.begin() + static_cast<std::ptrdiff_t>(at + count));
        break;
      }
      case 4:  // truncate
        bytes.resize(position(bytes));
        break;
      case 5: {  // duplicate a chunk
        if (bytes.empty()) break;
        const std::size_t at = position(bytes) % bytes.size();
        const std::size_t count = std::min<std::size_t>(static_cast<std::size_t>(1 + below(256)), bytes.size() - at);
        const Bytes chunk(bytes.begin() + static_cast<std::ptrdiff_t>(at), bytes.begin() + static_cast<std::ptrdiff_t>(at + count));
        bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(position(bytes)), chunk.begin(), chunk.end());
        break;
      }
      case 6: {  // overwrite a run of digits (a number, a size) with a token
        const std::string token = kTokens[below(std::size(kTokens))];
        std::size_t at = position(bytes);
        while (at < bytes.size() && !std::isdigit(static_cast<unsigned char>(bytes[at]))) ++at;
        std::size_t end = at;
        while (end < bytes.size() && (std::isdigit(static_cast<unsigned char>(bytes[end])) || bytes[end] == std::byte{'.'}))
          ++end;
        bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(std::min(at, bytes.size())),
                    bytes.begin() + static_cast<std::ptrdiff_t>(std::min(end, bytes.size())));
        insertText(bytes, std::min(at, bytes.size()), token);
        break;
      }
      default:  // splice a token anywhere
        insertText(bytes, position(bytes), kTokens[below(std::size(kTokens))]);
    }
  }

  static void insertText(Bytes& bytes, std::size_t at, const std::string& text) {
    const auto* first = reinterpret_cast<const std::byte*>(text.data());
    bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(at), first, first + text.size());
  }

  std::mt19937_64 random_;
};

Bytes textBytes(const std::string& text) {
  Bytes bytes(text.size());
  std::memcpy(bytes.data(), text.data(), text.size());
  return bytes;
}

void writeBytes(const fs::path& path, const Bytes& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

bool sameArrays(const io::NpyArray& a, const io::NpyArray& b) {
  return a.shape == b.shape && a.dtype == b.dtype && sameBits(a.floats, b.floats) && a.ints == b.ints;
}

// Reads one mutated file: true for a read whose result round-trips, false for a smokesvd::Error. Any other
// exception escapes and fails the test with the case's description.
using Reader = std::function<void(const fs::path& file)>;

struct Tally {
  int reads = 0, errors = 0;
  double slowest = 0;
};

Tally fuzz(const std::string& format, const Bytes& valid, const fs::path& file, const Reader& read, uint64_t seed) {
  Tally tally;
  writeBytes(file, valid);
  EXPECT_NO_THROW(read(file)) << format << ": the unmutated file must read";
  Mutator mutator(seed);
  for (int i = 0; i < kCasesPerFormat; ++i) {
    const Bytes mutated = mutator.mutate(valid);
    writeBytes(file, mutated);
    const auto start = std::chrono::steady_clock::now();
    try {
      read(file);
      ++tally.reads;
    } catch (const Error&) {
      ++tally.errors;
    } catch (const std::exception& other) {
      ADD_FAILURE() << format << " case " << i << " (seed " << seed << "): not a smokesvd::Error but "
                    << typeid(other).name() << ": " << other.what();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    tally.slowest = std::max(tally.slowest, seconds);
    EXPECT_LT(seconds, kSecondsPerCase) << format << " case " << i << " (seed " << seed << ")";
    if (::testing::Test::HasFailure()) {
      writeBytes(fs::path(file).replace_extension(".failed"), mutated);
      break;
    }
  }
  std::cout << format << ": " << kCasesPerFormat << " mutations, " << tally.reads << " read, " << tally.errors
            << " refused, slowest " << tally.slowest * 1e3 << " ms\n";
  return tally;
}

io::NpyArray smallArray() {
  std::vector<float> values(2 * 3 * 4);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.25f * static_cast<float>(i) - 1.0f;
  return io::NpyArray::fromFloats({2, 3, 4}, values);
}

class FuzzReaders : public ::testing::Test {
 protected:
  io::TemporaryFolder folder_{"fuzz", io::TemporaryFolder::memoryBacked()};
};

TEST_F(FuzzReaders, Npy) {
  fuzz("npy", io::serializeNpy(smallArray()), folder_ / "a.npy", [](const fs::path& file) {
    const io::NpyArray array = io::readNpy(file);
    ASSERT_EQ(static_cast<std::size_t>(array.numel()), array.dtype == io::DType::Float32 ? array.floats.size() : array.ints.size());
    EXPECT_TRUE(sameArrays(io::parseNpy(io::serializeNpy(array), "round trip"), array));
  }, 101);
}

TEST_F(FuzzReaders, Npz) {
  const fs::path valid = folder_ / "valid.npz";
  io::writeNpz(valid, {{"density", smallArray()}, {"flags", io::NpyArray::fromInts({3}, {1, 2, 4})}}, false);
  for (bool compressed : {false, true}) {
    if (compressed) io::writeNpz(valid, {{"density", smallArray()}, {"flags", io::NpyArray::fromInts({3}, {1, 2, 4})}});
    fuzz(compressed ? "npz (deflated)" : "npz (stored)", io::readFileBytes(valid), folder_ / "a.npz", [&](const fs::path& file) {
      const std::map<std::string, io::NpyArray> arrays = io::readNpz(file);
      const fs::path copy = folder_ / "copy.npz";
      io::writeNpz(copy, arrays);
      const std::map<std::string, io::NpyArray> again = io::readNpz(copy);
      ASSERT_EQ(again.size(), arrays.size());
      for (const auto& [key, array] : arrays) EXPECT_TRUE(sameArrays(again.at(key), array)) << key;
    }, compressed ? 202 : 203);
  }
}

TEST_F(FuzzReaders, Safetensors) {
  const std::vector<io::NamedArray> tensors = {{"conv.weight", {2, 1, 3}, {1, 2, 3, 4, 5, 6}}, {"conv.bias", {2}, {0.5f, -0.5f}}};
  fuzz("safetensors", io::serializeSafetensors(tensors, {{"format", "pt"}}), folder_ / "a.safetensors", [](const fs::path& file) {
    const io::SafetensorsFile read = io::readSafetensors(file);
    const io::SafetensorsFile again = io::parseSafetensors(io::serializeSafetensors(read.tensors, read.metadata), "round trip");
    ASSERT_EQ(again.tensors.size(), read.tensors.size());
    for (std::size_t i = 0; i < read.tensors.size(); ++i) {
      EXPECT_EQ(again.tensors[i].shape, read.tensors[i].shape);
      EXPECT_EQ(static_cast<int64_t>(read.tensors[i].values.size()), numElements(read.tensors[i].shape));
      EXPECT_TRUE(sameBits(again.tensors[i].values, read.tensors[i].values));
    }
    EXPECT_EQ(again.metadata, read.metadata);
  }, 303);
}

TEST_F(FuzzReaders, SceneJson) {
  const std::string scene = R"({"resolution": [12, 20, 10], "frames": 4, "steps_per_frame": 2, "dt": 0.5,
    "boundaries": {"y_high": "open", "x_low": "wall"}, "advection": {"scheme": "maccormack", "strength": 1},
    "pressure": {"tolerance": 1e-4, "max_iterations": 50}, "gravity": [0, -1, 0],
    "buoyancy": {"density": 0.5, "temperature": 1.5}, "wind": {"acceleration": [[0, [0.1, 0, 0]], [3, [0, 0, 0.2]]]},
    "vorticity": 0.2,
    "obstacles": [{"shape": "box", "centre": [6, 10, 5], "half_size": [1, 2, 1], "frames": [1, -1]}],
    "sources": [{"shape": "cylinder", "centre": [6, 3, 5], "radius": 2, "half_height": 1, "axis": [0, 1, 0],
                 "density": [[0, 1], [2, 0.5]], "temperature": 1, "velocity": [0, 0.5, 0],
                 "noise": {"amplitude": 0.2, "scale": 3, "velocity": [0, 1, 0], "seed": 7}, "mode": "add"}],
    "render": {"views": 4, "width": 12, "height": 20, "step": 0.5, "absorption": 0.3, "exposure": 1.2,
               "light": {"direction": [1, 1, 0], "intensity": 2, "absorption": 0.5}}})";
  fuzz("scene.json", textBytes(scene), folder_ / "scene.json", [](const fs::path& file) {
    const sim::Scene read = sim::readScene(file);
    EXPECT_EQ(sim::parseScene(sim::sceneToJson(read), "round trip"), read);
    EXPECT_LE(read.resolution.cells(), kMaxGridCells);
  }, 404);
}

TEST_F(FuzzReaders, CalibrationJson) {
  const std::string info = R"({"train_videos": [
      {"file_name": "a.mp4", "camera_angle_x": 0.4, "camera_hw": [40, 20],
       "transform_matrix": [[1, 0, 0, 0.1], [0, 1, 0, 0.2], [0, 0, 1, 3], [0, 0, 0, 1]]},
      {"file_name": "b.mp4", "camera_angle_x": 0.5, "camera_hw": [40, 20], "frame_rate": 30, "frame_num": 120,
       "transform_matrix": [[0, 0, 1, 3], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]]}],
    "test_videos": [],
    "voxel_scale": [0.5, 0.75, 0.5], "voxel_matrix": [[1, 0, 0, -0.25], [0, 1, 0, 0], [0, 0, 1, -0.25], [0, 0, 0, 1]]})";
  fuzz("info.json", textBytes(info), folder_ / "info.json", [](const fs::path& file) {
    const Calibration read = readCalibration(file);
    ASSERT_FALSE(read.views.empty());
    for (const CalibratedView& view : read.views) {
      EXPECT_GT(view.width, 0);
      EXPECT_GT(view.height, 0);
      EXPECT_TRUE(std::isfinite(view.cameraAngleX));
    }
  }, 505);
}

}  // namespace
}  // namespace smokesvd::testing

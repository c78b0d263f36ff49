#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <thread>

#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "runtime/error.h"
#include "tests/harness/test_data.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

class NpyTest : public ::testing::Test {
 protected:
  fs::path path(const std::string& name) const { return directory_ / name; }

  void writeBytes(const fs::path& file, const std::vector<std::byte>& bytes) const {
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }

  io::TemporaryFolder directory_{"npy"};
};

TEST_F(NpyTest, RoundTripsFloatAndIntOfOddShapes) {
  for (const Shape& shape : {Shape{}, Shape{1}, Shape{7}, Shape{3, 5}, Shape{2, 3, 5, 3}, Shape{0, 4}}) {
    std::vector<float> floats(static_cast<std::size_t>(numElements(shape)));
    std::vector<int32_t> ints(floats.size());
    for (std::size_t i = 0; i < floats.size(); ++i) {
      floats[i] = static_cast<float>(i) * 0.25f - 3.0f;
      ints[i] = static_cast<int32_t>(i) - 7;
    }
    io::writeNpy(path("f.npy"), io::NpyArray::fromFloats(shape, floats));
    io::writeNpy(path("i.npy"), io::NpyArray::fromInts(shape, ints));
    const io::NpyArray f = io::readNpy(path("f.npy"));
    const io::NpyArray i = io::readNpy(path("i.npy"));
    EXPECT_EQ(f.shape, shape);
    EXPECT_EQ(f.floats, floats);
    EXPECT_EQ(i.dtype, io::DType::Int32);
    EXPECT_EQ(i.ints, ints);
    EXPECT_FALSE(fs::exists(path("f.npy.tmp")));
  }
}

TEST_F(NpyTest, NpzRoundTripStoredAndDeflated) {
  std::map<std::string, io::NpyArray> arrays = {
      {"density", io::NpyArray::fromFloats({2, 3, 4}, std::vector<float>(24, 1.5f))},
      {"flags", io::NpyArray::fromInts({2, 3}, {1, 2, 1, 2, 1, 2})},
  };
  for (bool compress : {false, true}) {
    io::writeNpz(path("a.npz"), arrays, compress);
    const auto loaded = io::readNpz(path("a.npz"));
    ASSERT_EQ(loaded.size(), 2u);
    EXPECT_EQ(loaded.at("density").floats, arrays["density"].floats);
    EXPECT_EQ(loaded.at("flags").ints, arrays["flags"].ints);
    EXPECT_EQ(io::readNpzMember(path("a.npz"), "flags").shape, (Shape{2, 3}));
  }
}

// The archive is built in memory and written through "<path>.tmp" alone: nothing else is left beside it,
// an archive of no arrays reads back empty, and a second write replaces the first.
TEST_F(NpyTest, NpzIsWrittenThroughItsOwnTemporaryOnly) {
  io::writeNpz(path("empty.npz"), {});
  EXPECT_TRUE(io::readNpz(path("empty.npz")).empty());
  io::writeNpz(path("b.npz"), {{"x", io::NpyArray::fromFloats({2}, {1, 2})}});
  io::writeNpz(path("b.npz"), {{"y", io::NpyArray::fromFloats({1}, {3})}});
  const auto loaded = io::readNpz(path("b.npz"));
  ASSERT_EQ(loaded.size(), 1u);
  EXPECT_EQ(loaded.at("y").floats, std::vector<float>{3});
  std::size_t entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(path("b.npz").parent_path())) {
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
    ++entries;
  }
  EXPECT_EQ(entries, 2u);
}

// The same arrays written at different times give the same bytes (fixed zip time stamps), so the
// outputs of a seeded simulation can be compared file by file.
TEST_F(NpyTest, NpzBytesDoNotDependOnTheTime) {
  const std::map<std::string, io::NpyArray> arrays = {{"density", io::NpyArray::fromFloats({3}, {1, 2, 3})}};
  auto bytes = [&](const char* name) {
    io::writeNpz(path(name), arrays);
    std::ifstream in(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string first = bytes("a.npz");
  std::this_thread::sleep_for(std::chrono::milliseconds(2100));  // zip times have a 2 s resolution
  EXPECT_EQ(first, bytes("b.npz"));
}

TEST_F(NpyTest, ReadsTheMantaflowReferenceFile) {
  const auto arrays = io::readNpz(testData("mantaflow/advect_32x48x32.npz"));
  EXPECT_EQ(arrays.at("density_in").shape, (Shape{32, 48, 32}));
  EXPECT_EQ(arrays.at("vel_mac").shape, (Shape{32, 48, 32, 3}));
  EXPECT_EQ(arrays.at("flags").dtype, io::DType::Int32);
}

TEST_F(NpyTest, MissingNpzKeyListsAvailableKeys) {
  io::writeNpz(path("a.npz"), {{"density", io::NpyArray::fromFloats({1}, {0.0f})}});
  try {
    io::readNpzMember(path("a.npz"), "velocity");
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("available: density"), std::string::npos) << error.what();
  }
}

TEST_F(NpyTest, RejectsBadFilesWithClearErrors) {
  const std::vector<std::byte> good = io::serializeNpy(io::NpyArray::fromFloats({4}, {1, 2, 3, 4}));
  auto expectError = [&](std::vector<std::byte> bytes, const std::string& needle) {
    writeBytes(path("bad.npy"), bytes);
    try {
      io::readNpy(path("bad.npy"));
      ADD_FAILURE() << "expected an error containing '" << needle << "'";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(needle), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find("bad.npy"), std::string::npos) << error.what();
    }
  };
  auto replace = [&](std::string from, std::string to) {
    std::string text(reinterpret_cast<const char*>(good.data()), good.size());
    text.replace(text.find(from), from.size(), to);
    std::vector<std::byte> bytes(text.size());
    std::memcpy(bytes.data(), text.data(), text.size());
    return bytes;
  };
  expectError(replace("<f4", "<f8"), "dtype '<f8'");
  expectError(replace("<f4", ">f4"), "dtype '>f4'");
  expectError(replace("False", "True "), "fortran_order");
  expectError(replace("(4,)", "(9,)"), "needs 36 data bytes");  // header lies about the size
  expectError(std::vector<std::byte>(good.begin(), good.end() - 3), "data bytes");  // truncated
  expectError(std::vector<std::byte>(good.begin(), good.begin() + 5), "not a .npy");
  // Headers are read exactly: a sign is not dropped, a lie about the size is not believed, every key
  // is known and given once. withHeader() pads the dictionary as NumPy does and adds 16 data bytes.
  auto withHeader = [](std::string header) {
    header.append((64 - (10 + header.size() + 1) % 64) % 64, ' ');
    header += '\n';
    std::vector<std::byte> bytes(10 + header.size() + 16);
    std::memcpy(bytes.data(), "\x93NUMPY\x01\x00", 8);
    bytes[8] = static_cast<std::byte>(header.size() & 0xff);
    bytes[9] = static_cast<std::byte>(header.size() >> 8);
    std::memcpy(bytes.data() + 10, header.data(), header.size());
    return bytes;
  };
  const std::string prefix = "{'descr': '<f4', 'fortran_order': False, 'shape': ";
  writeBytes(path("good.npy"), withHeader(prefix + "(4,), }"));
  EXPECT_EQ(io::readNpy(path("good.npy")).shape, (Shape{4}));  // the control
  expectError(withHeader(prefix + "(-16, 28, 16), }"), "negative dimension in shape (-16, 28, 16)");
  expectError(withHeader(prefix + "(4a), }"), "expected ','");
  expectError(withHeader(prefix + "(99999999999999999999,), }"), "is too large");
  expectError(withHeader(prefix + "(1048576, 1048576, 1048576), }"), "needs more data than the file's 16 bytes");
  expectError(withHeader(prefix + "(4,), 'extra': 1, }"), "unknown key 'extra'");
  expectError(withHeader("{'descr': '<f4', 'descr': '<f4', 'fortran_order': False, 'shape': (4,)}"), "gives 'descr' twice");
  expectError(withHeader("{'descr': '<f4', 'shape': (4,)}"), "no 'fortran_order' field");
  expectError(withHeader(prefix + "(4,)} trailing"), "text after its dictionary");
  writeBytes(path("bad.npz"), good);
  EXPECT_THROW(io::readNpz(path("bad.npz")), Error);
  EXPECT_THROW(io::readNpy(path("missing.npy")), Error);
  std::filesystem::create_directories(path("folder.npy"));
  std::filesystem::create_directories(path("folder.npz"));
  for (const auto& [read, name] : {std::pair<std::function<void()>, std::string>{[&] { io::readNpy(path("folder.npy")); }, "folder.npy"},
                                   {[&] { io::readNpz(path("folder.npz")); }, "folder.npz"},
                                   {[&] { io::readNpy(path("missing.npy")); }, "missing.npy"}}) {
    try {
      read();
      ADD_FAILURE() << name;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(name + (name == "missing.npy" ? ": no such file" : ": is a folder, expected a file")),
                std::string::npos)
          << error.what();
    }
  }
}

}  // namespace
}  // namespace smokesvd::testing

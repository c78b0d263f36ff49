#include <gtest/gtest.h>


#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "nets/io/safetensors.h"
#include "nets/io/temporary_folder.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

// A .safetensors file from its header text and data bytes, as any writer would lay it out.
std::vector<std::byte> fileOf(const std::string& header, const std::vector<std::byte>& data) {
  std::vector<std::byte> bytes(8 + header.size());
  const uint64_t length = header.size();
  std::memcpy(bytes.data(), &length, 8);
  std::memcpy(bytes.data() + 8, header.data(), header.size());
  bytes.insert(bytes.end(), data.begin(), data.end());
  return bytes;
}

template <typename T>
std::vector<std::byte> bytesOf(const std::vector<T>& values) {
  std::vector<std::byte> bytes(values.size() * sizeof(T));
  std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

// Parsing must fail with an Error whose message contains `expected`.
void expectRejected(const std::vector<std::byte>& bytes, const std::string& expected) {
  try {
    io::parseSafetensors(bytes, "bad.safetensors");
    ADD_FAILURE() << "accepted a file that should fail with '" << expected << "'";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("bad.safetensors"), std::string::npos) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << "message: " << message << "\nexpected: " << expected;
  }
}

class SafetensorsTest : public ::testing::Test {
 protected:
  fs::path path(const std::string& name) const { return directory_ / name; }

  io::TemporaryFolder directory_{"safetensors"};
};

TEST_F(SafetensorsTest, RoundTripsOddShapesAndMetadata) {
  std::vector<io::NamedArray> tensors;
  uint64_t seed = 1;
  for (const Shape& shape : {Shape{}, Shape{7}, Shape{3, 5}, Shape{5, 3, 3, 3}, Shape{0, 4}, Shape{2, 3, 1, 3, 3}}) {
    tensors.push_back({"layer" + std::to_string(seed) + ".weight", shape,
                       randomValues(static_cast<std::size_t>(numElements(shape)), seed)});
    ++seed;
  }
  const std::map<std::string, std::string> metadata = {{"format", "pt"}, {"note", "odd \"quoted\" text"}};
  io::writeSafetensors(path("w.safetensors"), tensors, metadata);
  EXPECT_FALSE(fs::exists(path("w.safetensors.tmp")));

  const io::SafetensorsFile file = io::readSafetensors(path("w.safetensors"));
  EXPECT_EQ(file.metadata, metadata);
  ASSERT_EQ(file.tensors.size(), tensors.size());
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    EXPECT_EQ(file.tensors[i].name, tensors[i].name);
    EXPECT_EQ(file.tensors[i].shape, tensors[i].shape);
    EXPECT_EQ(file.tensors[i].values, tensors[i].values);
  }
  EXPECT_EQ(file.find("layer2.weight")->shape, (Shape{7}));
  EXPECT_EQ(file.find("nothing"), nullptr);
}

TEST_F(SafetensorsTest, WritesTheReferenceLayout) {
  const std::vector<std::byte> bytes = io::serializeSafetensors({{"b", {2}, {1.0f, -2.0f}}, {"a", {1}, {0.5f}}});
  uint64_t headerBytes = 0;
  std::memcpy(&headerBytes, bytes.data(), 8);
  EXPECT_EQ((8 + headerBytes) % 8, 0u) << "data must start 8-byte aligned";
  const std::string header(reinterpret_cast<const char*>(bytes.data() + 8), headerBytes);
  EXPECT_EQ(header.substr(0, header.find_last_not_of(' ') + 1),
            R"({"b":{"dtype":"F32","shape":[2],"data_offsets":[0,8]},"a":{"dtype":"F32","shape":[1],)"
            R"("data_offsets":[8,12]}})");
  float values[3];
  std::memcpy(values, bytes.data() + 8 + headerBytes, 12);
  EXPECT_EQ(values[0], 1.0f);
  EXPECT_EQ(values[1], -2.0f);
  EXPECT_EQ(values[2], 0.5f);
}

TEST_F(SafetensorsTest, ReadsAFileWrittenByAnotherWriter) {
  // Keys in another order than the data, spaces in the JSON, header padding with spaces.
  const std::string header =
      R"({ "__metadata__": {"format": "pt"}, "w": {"dtype": "F32", "shape": [2, 1], "data_offsets": [4, 12]},)"
      R"( "b": {"dtype": "F32", "shape": [1], "data_offsets": [0, 4]} }   )";
  const io::SafetensorsFile file = io::parseSafetensors(fileOf(header, bytesOf<float>({3, 1, 2})), "x");
  ASSERT_EQ(file.tensors.size(), 2u);
  EXPECT_EQ(file.tensors[0].name, "b");  // data order
  EXPECT_EQ(file.tensors[0].values, (std::vector<float>{3}));
  EXPECT_EQ(file.tensors[1].shape, (Shape{2, 1}));
  EXPECT_EQ(file.tensors[1].values, (std::vector<float>{1, 2}));
  EXPECT_EQ(file.metadata.at("format"), "pt");
}

TEST_F(SafetensorsTest, ConvertsHalfBfloatAndDouble) {
  const std::vector<uint16_t> half = {0x3C00, 0xC000, 0x0001, 0x7C00, 0x3555, 0x8000};
  const std::vector<uint16_t> bfloat = {0x3F80, 0xC049, 0x0000};
  const std::vector<double> doubles = {0.1, -1e30, 3.0};
  std::vector<std::byte> data = bytesOf(half);
  const std::vector<std::byte> b = bytesOf(bfloat), d = bytesOf(doubles);
  data.insert(data.end(), b.begin(), b.end());
  data.insert(data.end(), d.begin(), d.end());
  const std::string header =
      R"({"h":{"dtype":"F16","shape":[6],"data_offsets":[0,12]},)"
      R"("bf":{"dtype":"BF16","shape":[3],"data_offsets":[12,18]},)"
      R"("d":{"dtype":"F64","shape":[3],"data_offsets":[18,42]}})";
  const io::SafetensorsFile file = io::parseSafetensors(fileOf(header, data), "mixed");
  const std::vector<float>& h = file.find("h")->values;
  EXPECT_EQ(h[0], 1.0f);
  EXPECT_EQ(h[1], -2.0f);
  EXPECT_EQ(h[2], std::ldexp(1.0f, -24));  // smallest subnormal
  EXPECT_TRUE(std::isinf(h[3]));
  EXPECT_EQ(h[4], 0.333251953125f);
  EXPECT_TRUE(std::signbit(h[5]) && h[5] == 0.0f);
  EXPECT_EQ(file.find("bf")->values, (std::vector<float>{1.0f, -3.140625f, 0.0f}));
  EXPECT_EQ(file.find("d")->values, (std::vector<float>{0.1f, -1e30f, 3.0f}));
}

TEST_F(SafetensorsTest, RejectsCorruptFilesWithClearErrors) {
  const std::vector<std::byte> eight = bytesOf<float>({1, 2});
  const auto one = [](const std::string& entry) { return "{\"t\":" + entry + "}"; };

  expectRejected(std::vector<std::byte>(5), "too short for the 8-byte header length");
  std::vector<std::byte> lying = fileOf(one(R"({"dtype":"F32","shape":[2],"data_offsets":[0,8]})"), eight);
  lying[0] = std::byte{0xff};
  lying[3] = std::byte{0x01};
  expectRejected(lying, "the header length says");
  expectRejected(fileOf(R"({"t": {"dtype": "F32", "shape": [2], )", eight), "not valid JSON");
  expectRejected(fileOf(R"(["t"])", {}), "must be a JSON object");
  expectRejected(fileOf(R"({"t":{"dtype":"F32","shape":[1],"data_offsets":[0,4]},)"
                        R"("t":{"dtype":"F32","shape":[1],"data_offsets":[4,8]}})",
                        eight),
                 "names 't' twice");
  expectRejected(fileOf(one(R"({"dtype":"F32","shape":[2],"data_offsets":[0,12]})"), eight), "run past");
  expectRejected(fileOf(one(R"({"dtype":"F32","shape":[2],"data_offsets":[8,0]})"), eight), "end before");
  expectRejected(fileOf(R"({"a":{"dtype":"F32","shape":[2],"data_offsets":[0,8]},)"
                        R"("b":{"dtype":"F32","shape":[1],"data_offsets":[4,8]}})",
                        eight),
                 "overlap tensor 'a'");
  expectRejected(fileOf(one(R"({"dtype":"F32","shape":[1],"data_offsets":[4,8]})"), eight), "belong to no tensor");
  expectRejected(fileOf(one(R"({"dtype":"F32","shape":[1],"data_offsets":[0,4]})"), eight),
                 "4 bytes after the last tensor");
  expectRejected(fileOf(one(R"({"dtype":"I64","shape":[1],"data_offsets":[0,8]})"), eight),
                 "dtype 'I64' is not supported");
  expectRejected(fileOf(one(R"({"dtype":"F33","shape":[2],"data_offsets":[0,8]})"), eight),
                 "dtype 'F33' is not a safetensors dtype");
  expectRejected(fileOf(one(R"({"dtype":"F32","shape":[3],"data_offsets":[0,8]})"), eight),
                 "shape [3] needs 12 bytes but data_offsets [0, 8] span 8");
  expectRejected(fileOf(one(R"({"dtype":"F32","shape":[-2],"data_offsets":[0,8]})"), eight),
                 "shape entry must be a non-negative integer");
  expectRejected(fileOf(one(R"({"dtype":"F32","shape":[4294967296, 4294967296, 4294967296],)"
                            R"("data_offsets":[0,8]})"),
                        eight),
                 "is too large");
  expectRejected(fileOf(one(R"({"dtype":"F32","shape":[2]})"), eight), "has no 'data_offsets'");
  expectRejected(fileOf(R"({"__metadata__":{"step":3}})", {}), "__metadata__ 'step' must be a string");
}

// Every prefix of a valid file and every single-byte corruption of its header either parses or
// fails with an Error: nothing crashes and no other exception escapes.
TEST_F(SafetensorsTest, TruncatedAndScrambledFilesNeverCrash) {
  const std::vector<std::byte> valid =
      io::serializeSafetensors({{"a.weight", {3, 2}, randomValues(6, 1)}, {"a.bias", {3}, randomValues(3, 2)}});
  for (std::size_t length = 0; length < valid.size(); ++length) {
    const std::vector<std::byte> prefix(valid.begin(), valid.begin() + static_cast<std::ptrdiff_t>(length));
    EXPECT_THROW(io::parseSafetensors(prefix, "prefix"), Error) << "prefix of " << length << " bytes";
  }
  std::mt19937 generator(7);
  uint64_t headerBytes = 0;
  std::memcpy(&headerBytes, valid.data(), 8);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<std::byte> scrambled = valid;
    const std::size_t at = generator() % (8 + headerBytes);
    scrambled[at] = static_cast<std::byte>(generator() & 0xff);
    try {
      io::parseSafetensors(scrambled, "scrambled");
    } catch (const Error&) {
    }
  }
}

class SafetensorsUploadTest : public GpuTest {};

TEST_F(SafetensorsUploadTest, UploadsByNameAndListsEveryMismatch) {
  const io::SafetensorsFile file{{{"conv.weight", {2, 1, 3, 3}, randomValues(18, 1)},
                                  {"conv.bias", {2}, {0.5f, -0.5f}},
                                  {"extra.weight", {1}, {1.0f}},
                                  {"norm.weight", {4}, {1, 1, 1, 1}}},
                                 {}};
  Tensor weight(context(), {2, 1, 3, 3}), bias(context(), {2}), norm(context(), {3}), missing(context(), {5});
  try {
    io::uploadNamed(file, {{"conv.weight", weight}, {"conv.bias", bias}, {"norm.weight", norm}, {"head.bias", missing}},
                    "w.safetensors");
    FAIL() << "a mismatching file was accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "w.safetensors does not match the model's tensors; 1 missing: head.bias; 1 unexpected: extra.weight; "
                 "1 with a different shape: norm.weight (expected [3], file has [4])");
  }
  // Not strict: missing and unexpected names are allowed, shapes must still agree.
  EXPECT_THROW(io::uploadNamed(file, {{"norm.weight", norm}}, "w.safetensors", false), Error);
  io::uploadNamed(file, {{"conv.weight", weight}, {"conv.bias", bias}, {"head.bias", missing}}, "w.safetensors", false);
  EXPECT_EQ(weight.download(), file.find("conv.weight")->values);
  EXPECT_EQ(bias.download(), (std::vector<float>{0.5f, -0.5f}));

  const std::vector<io::NamedArray> downloaded = io::downloadNamed({{"conv.bias", bias}});
  ASSERT_EQ(downloaded.size(), 1u);
  EXPECT_EQ(downloaded[0].name, "conv.bias");
  EXPECT_EQ(downloaded[0].shape, (Shape{2}));
  EXPECT_EQ(downloaded[0].values, (std::vector<float>{0.5f, -0.5f}));
}

}  // namespace
}  // namespace smokesvd::testing

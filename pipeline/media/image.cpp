#include "pipeline/media/image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "nets/io/file_io.h"
#include "runtime/error.h"

#include <stb/stb_image.h>

// stb_image_write's zlib compressor (compiled in stb_backend.cpp; its header does not declare it).
extern "C" unsigned char* stbi_zlib_compress(unsigned char* data, int length, int* outLength, int quality);

namespace smokesvd::media {
namespace {

namespace fs = std::filesystem;

std::vector<unsigned char> readBytes(const fs::path& path) {
  const std::string text = io::readTextFile(path);
  return {text.begin(), text.end()};
}

uint32_t crc32(const unsigned char* data, std::size_t size, uint32_t crc = 0) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t n = 0; n < 256; ++n) {
      uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

void putBigEndian(std::vector<unsigned char>& out, uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<unsigned char>(value >> shift));
}

void putChunk(std::vector<unsigned char>& out, const char type[4], const std::vector<unsigned char>& data) {
  putBigEndian(out, static_cast<uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  putBigEndian(out, crc32(out.data() + start, out.size() - start));
}

}  // namespace

Image Image::gray(int width, int height, float value) {
  Image image;
  image.width = width;
  image.height = height;
  image.values.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), value);
  return image;
}

Image readPng(const fs::path& path) {
  const std::vector<unsigned char> bytes = readBytes(path);
  const int length = static_cast<int>(bytes.size());
  int width = 0, height = 0, channels = 0;
  const bool sixteen = stbi_is_16_bit_from_memory(bytes.data(), length) != 0;
  std::unique_ptr<void, void (*)(void*)> pixels(
      sixteen ? static_cast<void*>(stbi_load_16_from_memory(bytes.data(), length, &width, &height, &channels, 0))
              : static_cast<void*>(stbi_load_from_memory(bytes.data(), length, &width, &height, &channels, 0)),
      stbi_image_free);
  if (!pixels)
    throw Error(path.string() + ": not a readable PNG (" + stbi_failure_reason() +
                "); expected an 8- or 16-bit PNG image");
  const double scale = sixteen ? 1.0 / 65535.0 : 1.0 / 255.0;
  auto sample = [&](std::size_t index) {
    return sixteen ? static_cast<const stbi_us*>(pixels.get())[index] * scale
                   : static_cast<const stbi_uc*>(pixels.get())[index] * scale;
  };
  Image image = Image::gray(width, height);
  const auto n = static_cast<std::size_t>(channels);
  for (std::size_t i = 0; i < image.values.size(); ++i) {
    const double value = channels >= 3 ? 0.299 * sample(n * i) + 0.587 * sample(n * i + 1) + 0.114 * sample(n * i + 2)
                                       : sample(n * i);
    image.values[i] = static_cast<float>(value);
  }
  return image;
}

void writePng(const fs::path& path, const Image& image, int bitDepth) {
  if (bitDepth != 8 && bitDepth != 16) throw Error(path.string() + ": PNG bit depth must be 8 or 16");
  if (image.channels != 1 && image.channels != 3) throw Error(path.string() + ": PNG needs 1 or 3 channels");
  if (image.width <= 0 || image.height <= 0 ||
      image.values.size() != static_cast<std::size_t>(image.width * image.height * image.channels))
    throw Error(path.string() + ": image size and data do not agree");
  const int bytesPerSample = bitDepth / 8;
  const std::size_t rowBytes = static_cast<std::size_t>(image.width * image.channels * bytesPerSample) + 1;
  std::vector<unsigned char> raw;
  raw.reserve(rowBytes * static_cast<std::size_t>(image.height));
  const double maximum = bitDepth == 16 ? 65535.0 : 255.0;
  for (int row = 0; row < image.height; ++row) {
    raw.push_back(0);  // filter type: none
    for (int i = 0; i < image.width * image.channels; ++i) {
      const float v = image.values[static_cast<std::size_t>(row * image.width * image.channels + i)];
      const double clamped = std::isnan(v) ? 0.0 : std::clamp(static_cast<double>(v), 0.0, 1.0);
      const auto level = static_cast<uint32_t>(std::lround(clamped * maximum));
      if (bitDepth == 16) raw.push_back(static_cast<unsigned char>(level >> 8));
      raw.push_back(static_cast<unsigned char>(level & 0xFF));
    }
  }
  int compressedLength = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> compressed(
      stbi_zlib_compress(raw.data(), static_cast<int>(raw.size()), &compressedLength, 8), std::free);
  if (!compressed) throw Error(path.string() + ": PNG compression failed");

  std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<unsigned char> header;
  putBigEndian(header, static_cast<uint32_t>(image.width));
  putBigEndian(header, static_cast<uint32_t>(image.height));
  header.push_back(static_cast<unsigned char>(bitDepth));
  header.push_back(image.channels == 3 ? 2 : 0);  // colour type: RGB or gray
  header.insert(header.end(), {0, 0, 0});          // deflate, adaptive filtering, no interlace
  putChunk(png, "IHDR", header);
  putChunk(png, "IDAT", {compressed.get(), compressed.get() + compressedLength});
  putChunk(png, "IEND", {});

  io::writeAtomically(path, [&](const fs::path& temporary) {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    if (!file) throw Error(path.string() + ": cannot write (is the folder there and writable?)");
    file.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
    if (!file) throw Error(path.string() + ": write failed");
  });
}

Image toRgb(const Image& gray) {
  Image rgb;
  rgb.width = gray.width;
  rgb.height = gray.height;
  rgb.channels = 3;
  rgb.values.reserve(gray.values.size() * 3);
  for (float v : gray.values) rgb.values.insert(rgb.values.end(), {v, v, v});
  return rgb;
}

Image resize(const Image& image, int width, int height) {
  Image out;
  out.width = width;
  out.height = height;
  out.channels = image.channels;
  out.values.resize(static_cast<std::size_t>(width * height * image.channels));
  const double sx = static_cast<double>(image.width) / width, sy = static_cast<double>(image.height) / height;
  for (int r = 0; r < height; ++r) {
    const double y = std::clamp((r + 0.5) * sy - 0.5, 0.0, image.height - 1.0);
    const int y0 = static_cast<int>(y), y1 = std::min(y0 + 1, image.height - 1);
    const double fy = y - y0;
    for (int c = 0; c < width; ++c) {
      const double x = std::clamp((c + 0.5) * sx - 0.5, 0.0, image.width - 1.0);
      const int x0 = static_cast<int>(x), x1 = std::min(x0 + 1, image.width - 1);
      const double fx = x - x0;
      for (int ch = 0; ch < image.channels; ++ch) {
        const double top = (1 - fx) * image.at(y0, x0, ch) + fx * image.at(y0, x1, ch);
        const double bottom = (1 - fx) * image.at(y1, x0, ch) + fx * image.at(y1, x1, ch);
        out.at(r, c, ch) = static_cast<float>((1 - fy) * top + fy * bottom);
      }
    }
  }
  return out;
}

std::vector<float> mirroredRows(std::vector<float> values, int width) {
  const auto w = static_cast<std::size_t>(width);
  if (width <= 0 || values.size() % w != 0)
    throw Error("mirror: " + std::to_string(values.size()) + " values are not rows of width " + std::to_string(width));
  for (std::size_t row = 0; row < values.size(); row += w)
    std::reverse(values.begin() + static_cast<std::ptrdiff_t>(row), values.begin() + static_cast<std::ptrdiff_t>(row + w));
  return values;
}

}  // namespace smokesvd::media

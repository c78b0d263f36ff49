// PNG images: 8- or 16-bit grayscale (and RGB for overlays), values as floats in [0, 1], row 0 at the top.
//
// Reading accepts any PNG that stb_image decodes (8/16-bit; gray, gray+alpha, RGB, RGBA); colour is turned
// into gray as 0.299 R + 0.587 G + 0.114 B and alpha is ignored. Writing clamps to [0, 1], rounds to the bit
// depth, and goes through "<path>.tmp" renamed into place. Errors name the file and what was expected.
#pragma once

#include <filesystem>
#include <vector>

namespace smokesvd::media {

struct Image {
  int width = 0, height = 0;
  int channels = 1;           // 1 gray, 3 RGB (interleaved)
  std::vector<float> values;  // height * width * channels, row-major, in [0, 1]

  static Image gray(int width, int height, float value = 0.0f);
  float& at(int row, int column, int channel = 0) {
    return values[static_cast<std::size_t>((row * width + column) * channels + channel)];
  }
  float at(int row, int column, int channel = 0) const {
    return values[static_cast<std::size_t>((row * width + column) * channels + channel)];
  }
};

// Reads a PNG as gray.
Image readPng(const std::filesystem::path& path);
// Writes `image` (1 or 3 channels) with 8 or 16 bits per sample.
void writePng(const std::filesystem::path& path, const Image& image, int bitDepth = 8);

// Gray -> RGB (each channel the gray value).
Image toRgb(const Image& gray);
// Bilinear resize of a gray or RGB image.
Image resize(const Image& image, int width, int height);
// Gray images (row-major, `width` values a row, any number of rows) mirrored left to right: each row reversed.
std::vector<float> mirroredRows(std::vector<float> values, int width);

}  // namespace smokesvd::media

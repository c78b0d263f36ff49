#include "pipeline/train/loss_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "pipeline/media/image.h"

namespace smokesvd::train {
namespace {

constexpr int kWidth = 720, kHeight = 400, kLeft = 48, kBottom = 24, kTop = 10, kRight = 10;

// A 3x5 pixel font for the axis labels.
const std::array<uint16_t, 13>& glyphs() {
  // Rows top to bottom, 3 bits each (bit 2 = left column): "0123456789e-."
  static const std::array<uint16_t, 13> g{0b111101101101111, 0b010110010010111, 0b111001111100111, 0b111001111001111,
                                          0b101101111001001, 0b111100111001111, 0b111100111101111, 0b111001001001001,
                                          0b111101111101111, 0b111101111001111, 0b111101111100111, 0b000000111000000,
                                          0b000000000000010};
  return g;
}

void text(media::Image& image, int x, int y, const std::string& s, float value) {
  const std::string order = "0123456789e-.";
  for (const char c : s) {
    const auto index = order.find(c);
    if (index != std::string::npos)
      for (int row = 0; row < 5; ++row)
        for (int col = 0; col < 3; ++col)
          if ((glyphs()[index] >> (14 - (row * 3 + col))) & 1)
            for (int k = 0; k < 3; ++k)
              if (x + col >= 0 && x + col < image.width && y + row >= 0 && y + row < image.height)
                image.at(y + row, x + col, k) = value;
    x += 4;
  }
}

void dot(media::Image& image, int x, int y, const std::array<float, 3>& colour) {
  if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
  for (int k = 0; k < 3; ++k) image.at(y, x, k) = colour[static_cast<std::size_t>(k)];
}

}  // namespace

void plotLosses(const std::filesystem::path& path, const CsvLog& log, std::size_t firstColumn) {
  media::Image image = media::toRgb(media::Image::gray(kWidth, kHeight, 0.08f));
  const auto& rows = log.rows();
  if (rows.size() >= 2) {
    double low = 1e300, high = -1e300;
    for (const auto& row : rows)
      for (std::size_t c = firstColumn; c < row.size(); ++c)
        if (row[c] > 0) {
          low = std::min(low, std::log10(row[c]));
          high = std::max(high, std::log10(row[c]));
        }
    if (low <= high) {
      low = std::floor(low);
      high = std::max(std::ceil(high), low + 1);
      const double firstStep = rows.front()[0], lastStep = std::max(rows.back()[0], firstStep + 1);
      auto px = [&](double step) { return kLeft + static_cast<int>((step - firstStep) / (lastStep - firstStep) * (kWidth - kLeft - kRight)); };
      auto py = [&](double value) {
        return kTop + static_cast<int>((high - std::log10(value)) / (high - low) * (kHeight - kTop - kBottom));
      };
      for (double decade = low; decade <= high; decade += 1) {
        const int y = py(std::pow(10.0, decade));
        for (int x = kLeft; x < kWidth - kRight; ++x) dot(image, x, y, {0.25f, 0.25f, 0.25f});
        text(image, 2, y - 2, "1e" + std::to_string(static_cast<int>(decade)), 0.7f);
      }
      text(image, kLeft, kHeight - 10, std::to_string(static_cast<int64_t>(firstStep)), 0.7f);
      const std::string last = std::to_string(static_cast<int64_t>(lastStep));
      text(image, kWidth - kRight - 4 * static_cast<int>(last.size()), kHeight - 10, last, 0.7f);
      static const std::array<std::array<float, 3>, 6> palette{{{0.95f, 0.45f, 0.3f}, {0.35f, 0.7f, 0.95f},
                                                                 {0.5f, 0.9f, 0.4f}, {0.95f, 0.8f, 0.3f},
                                                                 {0.8f, 0.5f, 0.95f}, {0.4f, 0.9f, 0.85f}}};
      const std::size_t window = std::max<std::size_t>(1, rows.size() / 100);
      for (std::size_t c = log.columns().size(); c-- > firstColumn;) {
        const std::array<float, 3> colour =
            c == firstColumn ? std::array<float, 3>{1, 1, 1} : palette[(c - firstColumn - 1) % palette.size()];
        int previousX = -1, previousY = -1;
        for (std::size_t r = 0; r < rows.size(); ++r) {
          double sum = 0;
          std::size_t count = 0;
          for (std::size_t k = r >= window ? r - window + 1 : 0; k <= r; ++k)
            if (rows[k][c] > 0) {
              sum += rows[k][c];
              ++count;
            }
          if (count == 0) continue;
          const int x = px(rows[r][0]), y = py(sum / static_cast<double>(count));
          if (previousX >= 0) {
            const int steps = std::max(std::abs(x - previousX), std::abs(y - previousY));
            for (int s = 0; s <= steps; ++s)
              dot(image, previousX + (x - previousX) * s / std::max(steps, 1), previousY + (y - previousY) * s / std::max(steps, 1), colour);
          }
          previousX = x;
          previousY = y;
        }
      }
    }
  }
  media::writePng(path, image);
}

}  // namespace smokesvd::train

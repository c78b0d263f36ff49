#include "pipeline/eval/comparison_sheet.h"

#include <algorithm>
#include <cmath>

#include "pipeline/media/text.h"
#include "runtime/error.h"

namespace smokesvd::eval {
namespace {

constexpr int kMinimumTileHeight = 112;
constexpr int kGap = 4;
constexpr int kTextScale = 1;

void place(media::Image& sheet, const media::Image& tile, int x, int y, int factor, bool error) {
  for (int r = 0; r < tile.height * factor; ++r)
    for (int c = 0; c < tile.width * factor; ++c) {
      const float v = tile.at(r / factor, c / factor);
      const int row = y + r, column = x + c;
      if (row >= sheet.height || column >= sheet.width) continue;
      if (error) {
        sheet.at(row, column, 0) = std::clamp(2.0f * v, 0.0f, 1.0f);
        sheet.at(row, column, 1) = 0.0f;
        sheet.at(row, column, 2) = std::clamp(-2.0f * v, 0.0f, 1.0f);
      } else {
        for (int k = 0; k < 3; ++k) sheet.at(row, column, k) = std::clamp(v, 0.0f, 1.0f);
      }
    }
}

}  // namespace

std::vector<int> sheetFrames(int frames, int count) {
  std::vector<int> chosen;
  if (frames <= 0 || count <= 0) return chosen;
  if (frames <= count || count == 1) {
    for (int t = 0; t < std::min(frames, count); ++t) chosen.push_back(count == 1 ? 0 : t);
    return chosen;
  }
  for (int i = 0; i < count; ++i) chosen.push_back(static_cast<int>(std::lround(static_cast<double>(i) * (frames - 1) / (count - 1))));
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  return chosen;
}

media::Image comparisonSheet(const std::string& caption, const std::vector<int>& frames, const std::vector<SheetRow>& rows) {
  if (rows.empty() || frames.empty()) throw Error("comparison sheet: nothing to show (no view or no frame)");
  int tileWidth = 0, tileHeight = 0, labelWidth = 0;
  for (const SheetRow& row : rows) {
    if (row.reference.size() != frames.size() || row.ours.size() != frames.size())
      throw Error("comparison sheet: row '" + row.label + "' has " + std::to_string(row.ours.size()) + " frames, expected " +
                  std::to_string(frames.size()));
    const int factor = std::max(1, (kMinimumTileHeight + row.ours[0].height - 1) / row.ours[0].height);
    tileWidth = std::max(tileWidth, row.ours[0].width * factor);
    tileHeight = std::max(tileHeight, row.ours[0].height * factor);
    labelWidth = std::max(labelWidth, media::textSize(row.label, kTextScale)[0]);
  }
  const int header = 2 * 14 * kTextScale + kGap;
  const int left = labelWidth + 2 * kGap;
  const int columns = static_cast<int>(frames.size()) * 3;
  const int width = std::max(left + columns * (tileWidth + kGap) + 2 * kGap * static_cast<int>(frames.size()),
                             media::textSize(caption, kTextScale)[0] + 2 * kGap);
  const int height = header + static_cast<int>(rows.size()) * (tileHeight + kGap) + kGap;
  media::Image sheet = media::toRgb(media::Image::gray(width, height, 0.12f));
  const std::array<float, 3> white{1, 1, 1}, grey{0.7f, 0.7f, 0.7f};
  media::drawText(sheet, kGap, kGap, caption, white, kTextScale);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const int x = left + static_cast<int>(f) * (3 * (tileWidth + kGap) + 2 * kGap);
    media::drawText(sheet, x, kGap + 14 * kTextScale, "frame " + std::to_string(frames[f]) + ": reference | ours | error", grey,
                    kTextScale);
  }
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const SheetRow& row = rows[r];
    const int y = header + static_cast<int>(r) * (tileHeight + kGap);
    media::drawText(sheet, kGap, y + tileHeight / 2 - 4, row.label, white, kTextScale);
    const int factor = std::max(1, (kMinimumTileHeight + row.ours[0].height - 1) / row.ours[0].height);
    for (std::size_t f = 0; f < frames.size(); ++f) {
      const int x = left + static_cast<int>(f) * (3 * (tileWidth + kGap) + 2 * kGap);
      media::Image error = row.ours[f];
      for (std::size_t i = 0; i < error.values.size(); ++i) error.values[i] -= row.reference[f].values[i];
      place(sheet, row.reference[f], x, y, factor, false);
      place(sheet, row.ours[f], x + tileWidth + kGap, y, factor, false);
      place(sheet, error, x + 2 * (tileWidth + kGap), y, factor, true);
    }
  }
  return sheet;
}

}  // namespace smokesvd::eval

// The one translation unit that compiles stb_easy_font, with its warnings silenced.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

#include "pipeline/media/text.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "runtime/error.h"

namespace smokesvd::media {

void drawText(Image& rgb, int x, int y, const std::string& text, std::array<float, 3> colour, int scale) {
  if (rgb.channels != 3) throw Error("draw text: the image must be RGB");
  std::vector<char> characters(text.begin(), text.end());
  characters.push_back('\0');
  struct Vertex {
    float x, y, z;
    unsigned char colour[4];
  };
  std::vector<Vertex> vertices(characters.size() * 300 / sizeof(Vertex) * 4 + 64);
  const int quads = stb_easy_font_print(0, 0, characters.data(), nullptr, vertices.data(),
                                        static_cast<int>(vertices.size() * sizeof(Vertex)));
  for (int q = 0; q < quads; ++q) {
    const Vertex* v = &vertices[static_cast<std::size_t>(4 * q)];
    const int x0 = x + scale * static_cast<int>(std::lround(v[0].x)), y0 = y + scale * static_cast<int>(std::lround(v[0].y));
    const int x1 = x + scale * static_cast<int>(std::lround(v[2].x)), y1 = y + scale * static_cast<int>(std::lround(v[2].y));
    for (int r = std::max(0, y0); r < std::min(rgb.height, y1); ++r)
      for (int c = std::max(0, x0); c < std::min(rgb.width, x1); ++c)
        for (int k = 0; k < 3; ++k) rgb.at(r, c, k) = colour[static_cast<std::size_t>(k)];
  }
}

std::array<int, 2> textSize(const std::string& text, int scale) {
  std::vector<char> characters(text.begin(), text.end());
  characters.push_back('\0');
  return {scale * stb_easy_font_width(characters.data()), scale * stb_easy_font_height(characters.data())};
}

}  // namespace smokesvd::media

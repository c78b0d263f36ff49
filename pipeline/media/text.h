// Labels on images: ASCII text drawn with stb_easy_font's segment font (about 6 x 7 pixels a character at
// scale 1, lines 12 pixels apart; '\n' starts a new line), for the sheets people look at.
#pragma once

#include <array>
#include <string>

#include "pipeline/media/image.h"

namespace smokesvd::media {

// Draws `text` with its top-left corner at (x, y) into an RGB image, each font pixel `scale` x `scale` pixels;
// what falls outside the image is dropped.
void drawText(Image& rgb, int x, int y, const std::string& text, std::array<float, 3> colour, int scale = 1);
// The size `text` takes at `scale`: {width, height} in pixels.
std::array<int, 2> textSize(const std::string& text, int scale = 1);

}  // namespace smokesvd::media

// The comparison sheet a person looks at (comparison.png): one row per view, for each chosen frame three tiles,
// reference | ours | error, each tile the view's image enlarged by a whole factor (nearest neighbour) to at
// least 112 pixels high. The error tile shows d = ours - reference in colour: red where ours is brighter, blue
// where it is darker, full strength at |d| >= 0.5 (both channels 0 where they agree). Labels name the view, its
// angle and resolution on the left and the frames on top; a caption line says what the sheet shows.
#pragma once

#include <string>
#include <vector>

#include "pipeline/media/image.h"

namespace smokesvd::eval {

struct SheetRow {
  std::string label;                      // e.g. "view_04  45.0 deg  16x28"
  std::vector<media::Image> reference, ours;  // one per frame
};

media::Image comparisonSheet(const std::string& caption, const std::vector<int>& frames, const std::vector<SheetRow>& rows);

// Up to `count` frames of a clip of `frames`, evenly spaced, first and last included.
std::vector<int> sheetFrames(int frames, int count);

}  // namespace smokesvd::eval

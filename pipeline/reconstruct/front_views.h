// The input of a reconstruction turned into front views in the networks' units (docs/reconstruction.md):
//
//   1. frames: a video (any format ffmpeg reads), a folder of PNG frames, or an .npy/.npz image stack
//      [T, H, W]; colour becomes luminance (0.299 R + 0.587 G + 0.114 B);
//   2. region: `box` takes each whole frame as the front view of the reconstruction box (what
//      `smokesvd render` writes); `auto` finds the smoke (pixels above the black level by more than the
//      threshold, over the whole clip), and frames it as the training scenes are framed: its width about
//      60 % of the box's, its lowest pixel 4 % above the floor; `calibrated` crops the projection of a
//      calibrated volume box (NeRF-style info.json) into the chosen camera's frames. The region keeps the
//      preset's aspect ratio (pixels outside the frame are black) and is area-resampled to the preset's
//      image size;
//   2b. calibrated footage is filmed by a perspective camera, while the networks take an orthographic front
//      view: the front view is the footage rectified onto the box's mid-plane z = D/2, each front-view pixel
//      the area mean of the footage over the projection of that pixel's square on the plane (exact for smoke
//      in the mid-plane, and the magnification of the near and far faces averages out across the depth).
//      The crops as the camera saw them are kept beside it (inputFrames), with the camera over the crop
//      (inputCamera), so that later stages fit the footage through its own camera. `orthographic` skips the
//      rectification and takes the crop as the orthographic front view;
//   3. intensity: w = max(0, (v - black) * gain - threshold) / (1 - threshold), clamped to 1, where the
//      black level is the 2nd percentile of the clip (or the first frame, per pixel, with
//      --background first) and the gain maps the clip's 99.9th percentile to `target` (0.9: how bright
//      thick smoke renders in the networks' units). `--intensity none` keeps the values (black 0, gain 1,
//      threshold 0); a number sets the gain.
// The mapping and the region are recorded in run.json: renders of the result map back to the footage
// by v = black + w / gain.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/camera/camera.h"
#include "pipeline/media/image.h"
#include "pipeline/preset.h"

namespace smokesvd::reconstruct {

enum class Framing { Box, Auto, Calibrated };
enum class Background { Level, First };

struct InputOptions {
  std::filesystem::path input;
  int first = 0, count = -1;      // frames [first, first + count) of the input (count -1: to the end)
  Framing framing = Framing::Auto;
  std::filesystem::path calibration;  // info.json (Framing::Calibrated)
  std::string camera;                 // the calibrated view the input was filmed by (its file name)
  std::string intensity = "auto";     // "auto", "none" or a gain
  Background background = Background::Level;
  float target = 0.9f;
  float threshold = 0.02f;
  bool orthographic = false;          // calibrated input: the crop as the front view, not rectified
};

struct Region {
  double x0 = 0, y0 = 0, width = 0, height = 0;  // in source pixels (may extend past the frame)
};

struct IntensityMapping {
  float black = 0, gain = 1, threshold = 0;
  bool perPixelBackground = false;
};

struct FrontViews {
  std::vector<std::vector<float>> frames;       // the front views (slot 0), each imageHeight x imageWidth, row 0 at the top
  std::vector<std::vector<float>> inputFrames;  // the crops as inputCamera saw them (equal to frames unless rectified)
  Camera inputCamera;                           // the camera of inputFrames: the calibrated camera over the region, or slot 0
  bool rectified = false;
  int sourceWidth = 0, sourceHeight = 0;
  double frameRate = 30;
  Region region;
  IntensityMapping mapping;
  std::optional<Camera> camera;  // the calibrated camera of the input, at the source resolution
  nlohmann::json describe() const;  // for run.json
};

// Errors name the input and what was expected (no frames, an unreadable file, a bad --frames range, NaN).
FrontViews readFrontViews(const InputOptions& options, const Preset& preset);

Framing parseFraming(const std::string& text);  // "box", "auto", "calibrated"

// The pieces of the input path that evaluation repeats for the other cameras (pipeline/eval):
// w = clamp(max(0, (v - black) * gain - threshold) / (1 - threshold), 0, 1) on every value (a per-pixel
// background is subtracted before, by the caller);
void applyMapping(std::vector<media::Image>& frames, const IntensityMapping& mapping);
// the projection of the box of `grid` into `camera`'s image, centred and bottom-aligned, widened to `aspect`
// (width / height);
Region calibratedRegion(const Camera& camera, const GridSize& grid, double aspect);
// area resampling of `region` of `image` to width x height (pixels outside the image are black): each output
// pixel averages the source over its footprint, at least one source pixel wide.
std::vector<float> resampleRegion(const media::Image& image, const Region& region, int width, int height);
// the orthographic view `front` of the mid-plane z = D/2 of `grid`, from `image` filmed by `source` (at the
// image's resolution): each pixel the area mean of the image over the bounding rectangle of the projection of
// the pixel's square on the plane.
std::vector<float> rectifyToMidPlane(const media::Image& image, const Camera& source, const Camera& front, const GridSize& grid);

}  // namespace smokesvd::reconstruct

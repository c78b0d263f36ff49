// The views an evaluation compares at, and the reference images it compares with (docs/evaluation.md).
//
// Every view has a camera through which the reconstruction is rendered, at the evaluation's resolution, with
// `supersample` x `supersample` rays per pixel averaged (an area average of the render over each pixel, as the
// footage is area-resampled), clamped to [0, 1] as a PNG would be. Views belong to one of three groups: the
// input view, the side view and the novel views.
//
// Units: images are compared either in the networks' units (`Units::Mapped`: the reference goes through the
// reconstruction's own intensity mapping, w = clamp(max(0, (v - black) gain - threshold) / (1 - threshold), 0, 1),
// exactly as the input did; renders are taken as they are), or in the footage's units (`Units::Footage`: the
// reference as it is, renders mapped back by v = black + w / gain, plus the per-pixel background where the
// reconstruction subtracted one). The mapping cannot be inverted exactly (everything at or below
// black + threshold / gain maps to 0), which is why `Mapped` is the default.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/camera/camera.h"
#include "pipeline/media/image.h"
#include "pipeline/reconstruct/front_views.h"
#include "pipeline/render/renderer.h"

namespace smokesvd::eval {

enum class ViewGroup { Input, Side, Novel };
const char* groupName(ViewGroup group);  // "input", "side", "novel"

enum class Units { Mapped, Footage };
Units parseUnits(const std::string& text);  // "mapped", "footage"

struct EvalView {
  std::string name;
  ViewGroup group = ViewGroup::Novel;
  Camera camera;               // at the evaluation resolution (before supersampling)
  int supersample = 1;
  bool hasReference = true;    // false: a view no camera filmed (the side view of footage): temporal metrics of ours only
  bool mirroredInputFloor = false;  // the input-view floor is the input view mirrored left-right here
  nlohmann::json description;  // camera, angle, image region, resolution
};

// Renders `density` [D, H, W] (host values on `grid`) through every view.
std::vector<media::Image> renderViews(Context& context, const std::vector<float>& density, const GridSize& grid,
                                      const std::vector<EvalView>& views, const render::RenderSettings& look);

// The reference images of an evaluation, one frame at a time.
class References {
 public:
  virtual ~References() = default;
  const std::vector<EvalView>& views() const { return views_; }
  // The reference of every view at reconstruction frame t, in the evaluation's units (an empty image for a view
  // without one). Frames are asked for in order.
  virtual std::vector<media::Image> frame(Context& context, int t) = 0;
  // A render of the reconstruction through view `view`, turned into the evaluation's units.
  virtual void toUnits(std::size_t view, media::Image& render) const = 0;
  // What the references are: data, frames, units, image regions.
  virtual nlohmann::json describe() const = 0;

 protected:
  std::vector<EvalView> views_;
};

// Clamps every value to [0, 1].
void clampUnit(media::Image& image);
// The mapping of `mapping` applied to one image (after subtracting `background` if it is not empty).
void mapIntensity(media::Image& image, const reconstruct::IntensityMapping& mapping, const media::Image* background);
// A render mapped back to footage units: black + w / gain (+ background).
void mapBack(media::Image& render, const reconstruct::IntensityMapping& mapping, const media::Image* background);
// The image mirrored left-right.
media::Image mirrored(const media::Image& image);

}  // namespace smokesvd::eval

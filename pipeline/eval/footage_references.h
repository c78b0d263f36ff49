// References from calibrated footage (a NeRF-style info.json and its videos, pipeline/camera/calibration.h): every
// calibrated camera is a view, the reconstruction's input camera the input view (first) and the others novel views
// (by their orbit angle); the
// reconstruction is rendered through each camera's own perspective camera, placed by the calibration's box on the
// reconstruction's grid, and compared with that camera's video frames. There is no side camera: the side view
// (orbit 90 degrees, orthographic, the preset's image size) has renders of the reconstruction only, for its
// temporal metrics.
//
// Image region and resolution (Region):
//   Box    the projection of the box into each camera, centred and bottom-aligned and widened to the preset's
//          aspect ratio, resampled to the preset's image size: for the input camera exactly the crop the
//          reconstruction was made from (its region in run.json must agree, else the calibration differs);
//   Frame  each whole frame, area-resampled to `width` pixels across (its height keeping the frame's aspect).
// The reference is each video frame with the reconstruction's intensity mapping applied at the source resolution
// (after subtracting the camera's own first frame where the mapping subtracted one per pixel), then area-resampled
// over the region, as the input was; one mapping for every camera (one rig, one exposure). Reconstruction frame t
// is video frame first + t. The input-view floor is the input camera's reference as it is (the cameras stay
// within 90 degrees of the input).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/camera/calibration.h"
#include "pipeline/eval/eval_views.h"
#include "pipeline/eval/image_metrics.h"
#include "pipeline/eval/fields.h"

namespace smokesvd::eval {

enum class Region { Box, Frame };
Region parseRegion(const std::string& text);  // "box", "frame"

struct FootageOptions {
  std::filesystem::path calibration, videos;
  std::vector<std::string> selected;  // camera file names or their stems (empty: every camera)
  Region region = Region::Box;
  int width = 270;                    // Region::Frame
  int supersample = 2;                // rays per pixel along each axis
  Units units = Units::Mapped;
};

class FootageReferences : public References {
 public:
  FootageReferences(const ReconstructionRun& run, const FootageOptions& options);
  std::vector<media::Image> frame(Context& context, int t) override;
  void toUnits(std::size_t view, media::Image& render) const override;
  nlohmann::json describe() const override;

 private:
  struct Footage {
    std::filesystem::path video;
    int sourceWidth = 0, sourceHeight = 0;
    reconstruct::Region region;
    std::vector<media::Image> chunk;  // decoded frames [chunkStart, chunkStart + chunk.size())
    int chunkStart = -1;
    media::Image background;          // source resolution, when the mapping subtracts the first frame
    media::Image backgroundAtView;    // the same, resampled over the region
  };
  const media::Image& sourceFrame(Footage& footage, int t);

  ReconstructionRun run_;
  FootageOptions options_;
  std::vector<Footage> footage_;  // per view; the side view has none (empty video)
};

}  // namespace smokesvd::eval

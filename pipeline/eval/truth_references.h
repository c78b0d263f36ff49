// References from a simulated truth (smokesvd simulate's scene folder): the 16 orbit views of the method
// (slots 0..15 at 11.25 i degrees, orthographic, the preset's image size; slot 0 the input view, slot 8 the side
// view, the 14 others novel), where the truth density, converted to the networks' units of the reconstruction's
// box (rho * absorption_scene / absorption_box), and the reconstruction are rendered with one look: the
// reconstruction's (absorption of run.json's box, ambient 1, no light). Reconstruction frame t is truth frame
// first + t, first being the reconstruction's first input frame.
//
// The reconstruction must have taken the whole frame as the box's front view (--framing box), so that its box is
// the truth's; a truth of another resolution, or with fewer frames than the reconstruction covers, is an Error.
// The input-view floor is the input view as it is at views below 90 degrees and mirrored from 90 degrees on
// (the view at 180 degrees of an unlit volume is the mirrored input view).
#pragma once

#include <vector>

#include "pipeline/eval/eval_views.h"
#include "pipeline/eval/fields.h"

namespace smokesvd::eval {

class TruthReferences : public References {
 public:
  // `selected`: slot numbers to evaluate (empty: all 16; the input view is always evaluated).
  TruthReferences(const ReconstructionRun& run, TruthScene truth, const std::vector<int>& selected, Units units);
  std::vector<media::Image> frame(Context& context, int t) override;
  void toUnits(std::size_t view, media::Image& render) const override;
  nlohmann::json describe() const override;

  const TruthScene& truth() const { return truth_; }
  int truthFrame(int t) const { return run_.firstFrame + t; }

 private:
  std::vector<media::Image> raw(Context& context, int t) const;

  ReconstructionRun run_;
  TruthScene truth_;
  Units units_;
  std::vector<media::Image> background_;  // per view: the first frame, when the mapping subtracted it per pixel
};

}  // namespace smokesvd::eval

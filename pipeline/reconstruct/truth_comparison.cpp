#include "pipeline/reconstruct/truth_comparison.h"

#include <algorithm>
#include <cmath>

#include "nets/io/npy.h"
#include "pipeline/media/image.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/preset.h"
#include "pipeline/render/render_images.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/train/view_losses.h"
#include "runtime/error.h"

namespace smokesvd::reconstruct {
namespace fs = std::filesystem;
namespace {

std::vector<float> density(const fs::path& run, int frame, const Shape& expected) {
  const fs::path path = run / "fields" / ("density_" + sim::frameName(frame) + ".npz");
  const io::NpyArray a = io::readNpzMember(path, "density");
  if (a.shape != expected)
    throw Error(path.string() + ": density of shape " + toString(a.shape) + ", expected " + toString(expected));
  return a.toFloat();
}

}  // namespace

nlohmann::json TruthComparison::toJson() const {
  return {{"frames", frames},
          {"psnr_input_view", inputPsnr},
          {"psnr_side_view", sidePsnr},
          {"psnr_novel_views", novelPsnr},
          {"density_rmse", densityRmse},
          {"floor_black", {{"input_view", blackInput}, {"side_view", blackSide}, {"novel_views", blackNovel}}},
          {"floor_input_as_view", {{"side_view (mirrored)", frontAsSide}, {"novel_views", frontAsNovel}}},
          {"views", "input 0 deg, side 90 deg, novel 45, 67.5, 112.5, 135 deg; whole images at the preset's size; "
                    "PSNR per image (range 1), averaged over frames and views"}};
}

TruthComparison compareWithTruth(Context& context, const fs::path& reconstruction, const fs::path& truth,
                                 const std::string& presetName) {
  const Preset& p = preset(presetName);
  render::RenderSettings look;
  look.absorption = p.absorption;
  const std::vector<double> angles{0, 90, 45, 67.5, 112.5, 135};
  std::vector<Camera> cameras;
  for (const double a : angles) cameras.push_back(networks::orbitCameraAt(p, a));
  TruthComparison c;
  const Shape volume = p.grid.volume();
  for (int t = 0; fs::exists(reconstruction / "fields" / ("density_" + sim::frameName(t) + ".npz")); ++t) {
    const std::vector<float> recon = density(reconstruction, t, volume), real = density(truth, t, volume);
    const auto r = render::renderImages(context, Tensor::fromHost(context, volume, recon), cameras, look);
    const auto s = render::renderImages(context, Tensor::fromHost(context, volume, real), cameras, look);
    const std::vector<float> black(s[0].values.size(), 0.0f);
    c.inputPsnr += train::psnr(r[0].values, s[0].values);
    c.sidePsnr += train::psnr(r[1].values, s[1].values);
    c.blackInput += train::psnr(black, s[0].values);
    c.blackSide += train::psnr(black, s[1].values);
    c.frontAsSide += train::psnr(media::mirroredRows(s[0].values, s[0].width), s[1].values);
    for (std::size_t v = 2; v < angles.size(); ++v) {
      c.novelPsnr += train::psnr(r[v].values, s[v].values) / 4;
      c.blackNovel += train::psnr(black, s[v].values) / 4;
      c.frontAsNovel += train::psnr(s[0].values, s[v].values) / 4;
    }
    double sum = 0;
    for (std::size_t i = 0; i < recon.size(); ++i) sum += (static_cast<double>(recon[i]) - real[i]) * (recon[i] - real[i]);
    c.densityRmse += std::sqrt(sum / static_cast<double>(recon.size()));
    ++c.frames;
  }
  if (c.frames == 0) throw Error(reconstruction.string() + ": no reconstructed frames (fields/density_0000.npz)");
  for (double* v : {&c.inputPsnr, &c.sidePsnr, &c.novelPsnr, &c.densityRmse, &c.blackInput, &c.blackSide, &c.blackNovel,
                    &c.frontAsSide, &c.frontAsNovel})
    *v /= c.frames;
  return c;
}

}  // namespace smokesvd::reconstruct

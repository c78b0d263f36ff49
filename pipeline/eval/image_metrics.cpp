#include "pipeline/eval/image_metrics.h"

#include <cmath>
#include <map>
#include <string>

#include "nets/ops/reduce_axes.h"
#include "runtime/error.h"

namespace smokesvd::eval {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{16, 4, 1};

std::string sizeText(const media::Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

}  // namespace

double psnrOf(double mse) { return mse <= 1e-10 ? kPsnrCap : 10.0 * std::log10(1.0 / mse); }

double ImageScore::rmse() const { return std::sqrt(mse); }
double ImageScore::psnr() const { return psnrOf(mse); }

void recordImageScores(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& mse, const Tensor& ssim) {
  if (a.rank() != 3 || a.shape() != b.shape())
    throw Error("image scores: expected two image stacks [N, H, W] of one shape, got " + toString(a.shape()) + " and " +
                toString(b.shape()));
  const int64_t n = a.size(0), height = a.size(1), width = a.size(2);
  if (height < kSsimWindow || width < kSsimWindow)
    throw Error("image scores: images of " + std::to_string(width) + "x" + std::to_string(height) +
                " pixels are smaller than the 11 x 11 SSIM window");
  if (mse.numel() != n || ssim.numel() != n)
    throw Error("image scores: the outputs need " + std::to_string(n) + " elements, got " + toString(mse.shape()) +
                " and " + toString(ssim.shape()));
  const int64_t mapWidth = width - kSsimWindow + 1, mapHeight = height - kSsimWindow + 1;
  const Tensor map(stream.context(), {n, mapHeight, mapWidth});
  const struct {
    int32_t width, height, images;
  } push{static_cast<int32_t>(width), static_cast<int32_t>(height), static_cast<int32_t>(n)};
  stream.dispatch(stream.kernel("eval/ssim", kWorkgroup), {a, b, map}, push,
                  {static_cast<uint32_t>((mapWidth + kWorkgroup[0] - 1) / kWorkgroup[0]),
                   static_cast<uint32_t>((mapHeight + kWorkgroup[1] - 1) / kWorkgroup[1]), static_cast<uint32_t>(n)});
  const std::vector<int> pixels{1, 2};
  ops::reduceAxes(stream, ops::ReduceMap::SquaredDifference, a, &b, pixels, 1.0f / static_cast<float>(height * width), mse);
  ops::reduceAxes(stream, ops::ReduceMap::Identity, map, nullptr, pixels,
                  1.0f / static_cast<float>(mapHeight * mapWidth), ssim);
}

std::vector<ImageScore> compareImages(Context& context, std::span<const ImagePair> pairs) {
  std::map<std::pair<int, int>, std::vector<std::size_t>> bySize;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const media::Image& a = *pairs[i].a;
    const media::Image& b = *pairs[i].b;
    if (a.channels != 1 || b.channels != 1) throw Error("image scores: pair " + std::to_string(i) + " is not gray");
    if (a.width != b.width || a.height != b.height)
      throw Error("image scores: pair " + std::to_string(i) + " compares a " + sizeText(a) + " image with a " + sizeText(b) + " one");
    bySize[{a.width, a.height}].push_back(i);
  }
  std::vector<ImageScore> scores(pairs.size());
  for (const auto& [size, members] : bySize) {
    const auto [width, height] = size;
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    std::vector<float> a(members.size() * pixels), b(members.size() * pixels);
    for (std::size_t k = 0; k < members.size(); ++k) {
      std::copy(pairs[members[k]].a->values.begin(), pairs[members[k]].a->values.end(), a.begin() + static_cast<std::ptrdiff_t>(k * pixels));
      std::copy(pairs[members[k]].b->values.begin(), pairs[members[k]].b->values.end(), b.begin() + static_cast<std::ptrdiff_t>(k * pixels));
    }
    const Shape shape{static_cast<int64_t>(members.size()), height, width};
    const Tensor ta = Tensor::fromHost(context, shape, a), tb = Tensor::fromHost(context, shape, b);
    const Tensor mse(context, {shape[0]}), ssim(context, {shape[0]});
    Stream stream(context);
    recordImageScores(stream, ta, tb, mse, ssim);
    stream.submit();
    const std::vector<float> m = mse.download(), s = ssim.download();
    for (std::size_t k = 0; k < members.size(); ++k) scores[members[k]] = {m[k], s[k]};
  }
  return scores;
}

}  // namespace smokesvd::eval

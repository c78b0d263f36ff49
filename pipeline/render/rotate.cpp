#include "pipeline/render/rotate.h"

#include <cmath>
#include <numbers>

#include "runtime/error.h"

namespace smokesvd::render {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{64, 1, 1};
constexpr std::array<uint32_t, 3> kGridWorkgroup{16, 4, 1};

std::array<uint32_t, 3> gridGroups(int64_t x, int64_t y, int64_t z) {
  return {static_cast<uint32_t>((x + 15) / 16), static_cast<uint32_t>((y + 3) / 4), static_cast<uint32_t>(z)};
}

struct RotatePush {
  int32_t width, height, depth, channels;
  float cosA, sinA;
};

RotatePush rotatePush(const char* op, const Tensor& a, const Tensor& b, double angleDegrees) {
  if (a.rank() < 3 || a.shape() != b.shape() || a.numel() == 0)
    throw Error(std::string(op) + ": expected two volumes [..., D, H, W] of one shape, got " + toString(a.shape()) +
                " and " + toString(b.shape()));
  if (!std::isfinite(angleDegrees)) throw Error(std::string(op) + ": the angle must be finite");
  const double radians = angleDegrees * std::numbers::pi / 180.0;
  const int64_t voxels = a.size(-1) * a.size(-2) * a.size(-3);
  return {static_cast<int32_t>(a.size(-1)), static_cast<int32_t>(a.size(-2)), static_cast<int32_t>(a.size(-3)),
          static_cast<int32_t>(a.numel() / voxels), static_cast<float>(std::cos(radians)),
          static_cast<float>(std::sin(radians))};
}

}  // namespace

void rotate(Stream& stream, const Tensor& volume, double angleDegrees, const Tensor& rotated) {
  const RotatePush push = rotatePush("rotate", volume, rotated, angleDegrees);
  stream.dispatch(stream.kernel("render/rotate", kGridWorkgroup), {volume, rotated}, push,
                  gridGroups(push.width, push.height, static_cast<int64_t>(push.depth) * push.channels));
}

void rotateBackward(Stream& stream, const Tensor& gradRotated, double angleDegrees, const Tensor& gradVolume) {
  const RotatePush push = rotatePush("rotate backward", gradRotated, gradVolume, angleDegrees);
  stream.dispatchFlat(stream.kernel("render/rotate_adjoint", kWorkgroup), {gradRotated, gradVolume}, push,
                      static_cast<uint64_t>(gradVolume.numel()));
}

}  // namespace smokesvd::render

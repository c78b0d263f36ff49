#include "pipeline/render/lift.h"

#include "pipeline/render/atomics.h"
#include "runtime/error.h"

namespace smokesvd::render {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{64, 1, 1};

struct LiftPush {
  int32_t width, height, depth;
  int32_t imageWidth, imageHeight, views;
};

struct LiftAdjointPush {
  LiftPush lift;
  int32_t shardSize;
};

struct LiftRowsPush {
  LiftPush lift;
  int32_t firstView, viewCount;
};

LiftPush liftPush(const GridSize& g, const ViewSet& v) {
  return {static_cast<int32_t>(g.x), static_cast<int32_t>(g.y), static_cast<int32_t>(g.z),
          v.width, v.height, v.views};
}

void checkShapes(const char* op, const Tensor& images, const Tensor& lifted, const ViewSet& views,
                 const GridSize& grid) {
  const Shape imageShape{views.views, 1, views.height, views.width};
  const Shape liftedShape{views.views, grid.z, grid.y, grid.x};
  const Shape batchedShape{1, views.views, grid.z, grid.y, grid.x};
  if (images.shape() != imageShape)
    throw Error(std::string(op) + ": images must be " + toString(imageShape) + ", got " + toString(images.shape()));
  if (lifted.shape() != liftedShape && lifted.shape() != batchedShape)
    throw Error(std::string(op) + ": the lifted volume must be " + toString(liftedShape) + " or " +
                toString(batchedShape) + ", got " + toString(lifted.shape()));
}

}  // namespace

void lift(Stream& stream, const Tensor& images, const ViewSet& views, const GridSize& grid, const Tensor& lifted) {
  checkShapes("lift", images, lifted, views, grid);
  // One invocation per column (view, z, x) of the lifted volume.
  stream.dispatchFlat(stream.kernel("render/lift", kWorkgroup), {images, asVec4(views.table), lifted},
                      liftPush(grid, views), static_cast<uint64_t>(views.views) * grid.z * grid.x);
}

void liftBackward(Stream& stream, const Tensor& gradLifted, const ViewSet& views, const GridSize& grid,
                  const Tensor& gradImages) {
  checkShapes("lift backward", gradImages, gradLifted, views, grid);
  if (adjointsByPlanes(stream.context(), views)) {
    // One invocation per voxel plane adds into the pixel rows it projects onto, without atomics
    // (lift_adjoint_rows.comp).
    stream.fillZero(gradImages);
    dispatchByPlanes(stream, stream.kernel("render/lift_adjoint_rows", kPlaneWorkgroup),
                     {gradLifted, asVec4(views.table), gradImages}, grid.y, views.views,
                     static_cast<uint64_t>(grid.z) * (grid.x + 1) + 1,
                     [&](int first, int count) { return LiftRowsPush{liftPush(grid, views), first, count}; });
    return;
  }
  const uint64_t items = static_cast<uint64_t>(gradLifted.numel());
  const int shards = scatterShards(stream.context(), items, 0, kWorkgroup[0]);
  const Tensor target = scatterTarget(stream, gradImages, shards);
  const LiftAdjointPush push{liftPush(grid, views), shards > 1 ? static_cast<int32_t>(gradImages.numel()) : 0};
  dispatchScatter(stream, stream.kernel(scatterKernel(stream.context(), "render/lift_adjoint"), kWorkgroup),
                  {gradLifted, asVec4(views.table), target}, push, items, shards);
  sumShards(stream, target, shards, gradImages);
}

}  // namespace smokesvd::render

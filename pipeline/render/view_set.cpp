#include "pipeline/render/view_set.h"

#include "runtime/error.h"

namespace smokesvd::render {
namespace {

constexpr int kFloatsPerView = 36;

void put(std::vector<float>& out, const Vec3& v, double w) {
  for (double x : {v.x, v.y, v.z, w}) out.push_back(static_cast<float>(x));
}

}  // namespace

namespace {

std::vector<float> cameraTable(const ViewSet& set, std::span<const Camera> cameras) {
  std::vector<float> table;
  table.reserve(cameras.size() * kFloatsPerView);
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const Camera& c = cameras[i];
    if (c.width != set.width || c.height != set.height)
      throw Error("render views: camera " + std::to_string(i) + " renders " + std::to_string(c.width) + "x" +
                  std::to_string(c.height) + " pixels but camera 0 renders " + std::to_string(set.width) + "x" +
                  std::to_string(set.height) + "; one dispatch needs one image size");
    put(table, c.origin, c.perspective ? 1.0 : 0.0);
    put(table, c.originPerU, 0);
    put(table, c.originPerV, 0);
    put(table, c.direction, 0);
    put(table, c.directionPerU, 0);
    put(table, c.directionPerV, 0);
    for (int row = 0; row < 3; ++row)
      for (int column = 0; column < 4; ++column) table.push_back(static_cast<float>(c.projection[column][row]));
  }
  return table;
}

}  // namespace

ViewSet uploadViews(Context& context, std::span<const Camera> cameras) {
  if (cameras.empty()) throw Error("render views: no cameras given");
  ViewSet set;
  set.views = static_cast<int>(cameras.size());
  set.width = cameras[0].width;
  set.height = cameras[0].height;
  set.table = Tensor::fromHost(context, {set.views, kFloatsPerView}, cameraTable(set, cameras));
  return set;
}

void rewriteViews(const ViewSet& views, std::span<const Camera> cameras) {
  if (static_cast<int>(cameras.size()) != views.views)
    throw Error("render views: " + std::to_string(cameras.size()) + " cameras for a table of " +
                std::to_string(views.views) + " views");
  views.table.upload(cameraTable(views, cameras));
}

GridSize volumeGrid(const Tensor& volume, const char* what) {
  const Shape& shape = volume.shape();
  bool ok = shape.size() >= 3;
  for (std::size_t i = 0; ok && i + 3 < shape.size(); ++i) ok = shape[i] == 1;
  if (!ok || volume.numel() == 0)
    throw Error(std::string(what) + ": expected a volume [D, H, W] (leading dimensions of size 1 allowed), got " +
                toString(shape));
  return {.x = shape[shape.size() - 1], .y = shape[shape.size() - 2], .z = shape[shape.size() - 3]};
}

}  // namespace smokesvd::render

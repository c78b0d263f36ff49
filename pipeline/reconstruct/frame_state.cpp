#include "pipeline/reconstruct/frame_state.h"

#include "pipeline/networks/view_slots.h"
#include "runtime/error.h"
#include "runtime/stream.h"

namespace smokesvd::reconstruct {
namespace {

Tensor zeros(Context& context, const Shape& shape) {
  return Tensor::fromHost(context, shape, std::vector<float>(static_cast<std::size_t>(numElements(shape)), 0.0f));
}

}  // namespace

FrameState::FrameState(Context& context, const Preset& p)
    : side1(zeros(context, {1, 1, p.imageHeight, p.imageWidth})), side2(zeros(context, {1, 1, p.imageHeight, p.imageWidth})),
      sideRender1(zeros(context, {1, 1, p.imageHeight, p.imageWidth})),
      sideRender2(zeros(context, {1, 1, p.imageHeight, p.imageWidth})),
      pendingSide(zeros(context, {1, 1, p.imageHeight, p.imageWidth})),
      refined1(zeros(context, {networks::kSlots, 1, p.imageHeight, p.imageWidth})),
      refined2(zeros(context, {networks::kSlots, 1, p.imageHeight, p.imageWidth})),
      density(zeros(context, p.grid.volume())), inflow(zeros(context, p.grid.volume())) {}

void FrameState::advance(Stream& stream, const Tensor& side, const Tensor& sideRender, const Tensor& refined,
                         const Tensor& newDensity, const Tensor& newInflow) {
  stream.copy(side1, side2);
  stream.copy(sideRender1, sideRender2);
  stream.copy(refined1, refined2);
  stream.copy(side, side1);
  stream.copy(sideRender, sideRender1);
  stream.copy(refined, refined1);
  stream.copy(newDensity, density);
  stream.copy(newInflow, inflow);
}

std::map<std::string, io::NpyArray> FrameState::toArrays() const {
  std::map<std::string, io::NpyArray> arrays;
  const std::pair<const char*, const Tensor*> all[] = {{"side1", &side1}, {"side2", &side2}, {"side_render1", &sideRender1},
                                                       {"side_render2", &sideRender2}, {"pending_side", &pendingSide},
                                                       {"refined1", &refined1}, {"refined2", &refined2},
                                                       {"density", &density}, {"inflow", &inflow}};
  for (const auto& [name, tensor] : all) arrays[name] = io::NpyArray::fromFloats(tensor->shape(), tensor->download());
  arrays["frames_done"] = io::NpyArray::fromInts({1}, {framesDone});
  return arrays;
}

void FrameState::fromArrays(const std::map<std::string, io::NpyArray>& arrays, const std::string& source) {
  const std::pair<const char*, Tensor*> all[] = {{"side1", &side1}, {"side2", &side2}, {"side_render1", &sideRender1},
                                                 {"side_render2", &sideRender2}, {"pending_side", &pendingSide},
                                                 {"refined1", &refined1}, {"refined2", &refined2},
                                                 {"density", &density}, {"inflow", &inflow}};
  for (const auto& [name, tensor] : all) {
    const auto found = arrays.find(name);
    if (found == arrays.end() || found->second.shape != tensor->shape())
      throw Error(source + ": '" + name + "' is missing or of another shape (a checkpoint of another run?); "
                  "delete it or use --overwrite");
    tensor->upload(found->second.toFloat());
  }
  const auto done = arrays.find("frames_done");
  if (done == arrays.end()) throw Error(source + ": 'frames_done' is missing; delete it or use --overwrite");
  framesDone = static_cast<int>(done->second.toFloat().at(0));
}

}  // namespace smokesvd::reconstruct

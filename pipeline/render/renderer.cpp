#include "pipeline/render/renderer.h"

#include <cmath>

#include "pipeline/render/atomics.h"
#include "pipeline/render/corner_quads.h"
#include "pipeline/render/occupied_box.h"
#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd::render {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{64, 1, 1};

struct MarchPush {
  int32_t width, height, depth;
  int32_t imageWidth, imageHeight, views;
  float step;
};

struct MarchAdjointPush {
  MarchPush march;
  int32_t shardSize;
};

struct MarchRowsPush {
  MarchPush march;
  int32_t firstView, viewCount;
};

// What the march's adjoint reads.
struct MarchInputs {
  const Tensor& density;
  const Tensor& shadowOrDensity;  // the light-transmittance volume when lit
  const ViewSet& views;
  const RenderSettings& settings;
  GridSize grid;
  const Tensor& images;
  const Tensor& gradImages;
  Tensor look;
  bool lit;
};

struct LightPush {
  int32_t width, height, depth;
  float step;
};

void requireShape(const Tensor& tensor, const Shape& expected, const char* what) {
  if (tensor.shape() != expected)
    throw Error(std::string("render: ") + what + " must be " + toString(expected) + ", got " + toString(tensor.shape()));
}

Shape imageShape(const ViewSet& views) { return {views.views, 1, views.height, views.width}; }

MarchPush marchPush(const GridSize& g, const ViewSet& views, const RenderSettings& s) {
  return {static_cast<int32_t>(g.x), static_cast<int32_t>(g.y), static_cast<int32_t>(g.z),
          views.width, views.height, views.views, s.step};
}

LightPush lightPush(const GridSize& g, const DirectionalLight& light) {
  return {static_cast<int32_t>(g.x), static_cast<int32_t>(g.y), static_cast<int32_t>(g.z), light.step};
}

// The settings' own device look, or a fresh one from their fields.
Tensor deviceLook(Context& context, const RenderSettings& settings) {
  if (!settings.look.defined()) return lookTensor(context, settings);
  if (settings.look.numel() != 8) throw Error("render: the device look must hold 8 values, got " + toString(settings.look.shape()));
  return settings.look;
}

const Tensor& requireShadow(const Tensor* shadow, const GridSize& grid, const RenderSettings& settings) {
  if (!settings.light) throw Error("render: internal: shadow asked for without a light");
  if (shadow == nullptr) throw Error("render: a light needs the light-transmittance volume");
  requireShape(*shadow, grid.volume(), "the light-transmittance volume");
  return *shadow;
}

void requireFinite(float value, const char* field, bool positive) {
  if (!std::isfinite(value) || (positive ? value <= 0 : value < 0))
    throw Error(std::string("render settings: ") + field + " must be " + (positive ? "positive" : "non-negative") +
                " and finite, got " + std::to_string(value));
}

}  // namespace

void validate(const RenderSettings& settings) {
  requireFinite(settings.step, "step", true);
  if (settings.step < 1e-3f || (settings.light && settings.light->step < 1e-3f))
    throw Error("render settings: march steps must be at least 0.001 voxels");
  requireFinite(settings.absorption, "absorption", false);
  if (!std::isfinite(settings.ambient)) throw Error("render settings: ambient must be finite");
  if (settings.light) {
    requireFinite(settings.light->step, "light step", true);
    requireFinite(settings.light->absorption, "light absorption", false);
    if (!std::isfinite(settings.light->intensity)) throw Error("render settings: light intensity must be finite");
    const double n = glm::length(settings.light->direction);
    if (!(n > 1e-12) || !std::isfinite(n)) throw Error("render settings: light direction must be a non-zero vector");
  }
}

std::vector<float> lookValues(const RenderSettings& settings) {
  std::vector<float> values{settings.absorption, settings.ambient, 0, 0, 0, 0, 0, 0};
  if (settings.light) {
    const Vec3 l = glm::normalize(settings.light->direction);
    values[2] = settings.light->intensity;
    values[3] = settings.light->absorption;
    for (int axis = 0; axis < 3; ++axis) values[static_cast<std::size_t>(4 + axis)] = static_cast<float>(l[axis]);
  }
  return values;
}

Tensor lookTensor(Context& context, const RenderSettings& settings) {
  validate(settings);
  return Tensor::fromHost(context, {8}, lookValues(settings));
}

void uploadLook(const Tensor& look, const RenderSettings& settings) {
  validate(settings);
  if (look.numel() != 8) throw Error("render: a device look holds 8 values, got " + toString(look.shape()));
  look.upload(lookValues(settings));
}

void lightTransmittance(Stream& stream, const Tensor& density, const RenderSettings& settings, const Tensor& shadow,
                        const Tensor* box) {
  validate(settings);
  if (!settings.light) throw Error("render: light transmittance needs a light in the settings");
  const GridSize grid = volumeGrid(density, "render density");
  requireShape(shadow, grid.volume(), "the light-transmittance volume");
  stream.dispatchFlat(stream.kernel("render/light_transmittance", kWorkgroup),
                      {density, shadow, deviceLook(stream.context(), settings), asVec4(cornerQuads(stream, density)),
                       asVec4(box ? *box : occupiedBox(stream, density))},
                      lightPush(grid, *settings.light), static_cast<uint64_t>(density.numel()));
}

void march(Stream& stream, const Tensor& density, const Tensor* shadow, const ViewSet& views,
           const RenderSettings& settings, const Tensor& images, const Tensor* box) {
  validate(settings);
  const GridSize grid = volumeGrid(density, "render density");
  requireShape(images, imageShape(views), "the images");
  const bool lit = settings.light.has_value();
  const Tensor& shadowOrDensity = lit ? requireShadow(shadow, grid, settings) : density;
  const Kernel& kernel = stream.kernel("render/march", kWorkgroup, {lit ? 1 : 0});
  stream.dispatchFlat(kernel,
                      {density, shadowOrDensity, asVec4(views.table), images, deviceLook(stream.context(), settings),
                       asVec4(box ? *box : occupiedBox(stream, density))},
                      marchPush(grid, views, settings), static_cast<uint64_t>(images.numel()));
}

void render(Stream& stream, const Tensor& density, const ViewSet& views, const RenderSettings& settings,
            const Tensor& images) {
  if (!settings.light) {
    march(stream, density, nullptr, views, settings, images);
    return;
  }
  const GridSize grid = volumeGrid(density, "render density");
  Tensor shadow(stream.context(), grid.volume());
  const Tensor box = occupiedBox(stream, density);
  lightTransmittance(stream, density, settings, shadow, &box);
  march(stream, density, &shadow, views, settings, images, &box);
}

namespace {

// The most samples of `step` a ray takes across the box [-1/2, size + 1/2] when it moves along the axes whose
// box extents (size + 1) are given: the box's diagonal over them / step, and one more.
uint64_t samplesAcross(std::initializer_list<int64_t> sizes, double step) {
  double squared = 0;
  for (const int64_t size : sizes) squared += static_cast<double>(size + 1) * static_cast<double>(size + 1);
  return static_cast<uint64_t>(std::ceil(std::sqrt(squared) / step)) + 1;
}

// The march's adjoint into `direct` (and, lit, `gradShadow`) where every ray runs in a voxel row, on a CPU
// device: one invocation per voxel plane adds without atomics (march_adjoint_rows.comp).
void marchAdjointByPlanes(Stream& stream, const MarchInputs& in, const Tensor& direct, const Tensor& gradShadow) {
  stream.fillZero(direct);
  if (in.lit) stream.fillZero(gradShadow);
  // A ray in a voxel row stays in one horizontal section of the box.
  const uint64_t samples = samplesAcross({in.grid.x, in.grid.z}, in.settings.step);
  dispatchByPlanes(stream, stream.kernel("render/march_adjoint_rows", kPlaneWorkgroup, {in.lit ? 1 : 0}),
                   {in.density, in.shadowOrDensity, asVec4(in.views.table), in.images, in.gradImages, direct, gradShadow,
                    in.look},
                   in.grid.y, in.views.views, static_cast<uint64_t>(in.views.width) * (samples + 1) + 1,
                   [&](int first, int count) { return MarchRowsPush{marchPush(in.grid, in.views, in.settings), first, count}; });
}

// The march's adjoint into `direct` (and, lit, `gradShadow`) with float atomics, one invocation per pixel
// (march_adjoint.glsl), in deterministic shards on CPU devices.
void marchAdjointScattered(Stream& stream, const MarchInputs& in, const Tensor& direct, const Tensor& gradShadow) {
  const uint64_t samples = samplesAcross({in.grid.x, in.grid.y, in.grid.z}, in.settings.step);
  const uint64_t items = static_cast<uint64_t>(in.images.numel());
  const int shards = scatterShards(stream.context(), items, samples, kWorkgroup[0]);
  const MarchAdjointPush push{marchPush(in.grid, in.views, in.settings),
                              shards > 1 ? static_cast<int32_t>(in.density.numel()) : 0};
  const Tensor directTarget = scatterTarget(stream, direct, shards);
  const Tensor gradShadowTarget = in.lit ? scatterTarget(stream, gradShadow, shards) : gradShadow;
  dispatchScatter(stream, stream.kernel(scatterKernel(stream.context(), "render/march_adjoint"), kWorkgroup, {in.lit ? 1 : 0}),
                  {in.density, in.shadowOrDensity, asVec4(in.views.table), in.images, in.gradImages, directTarget,
                   gradShadowTarget, in.look},
                  push, items, shards);
  sumShards(stream, directTarget, shards, direct);
  if (in.lit) sumShards(stream, gradShadowTarget, shards, gradShadow);
}

}  // namespace

void renderBackward(Stream& stream, const Tensor& density, const Tensor* shadow, const ViewSet& views,
                    const RenderSettings& settings, const Tensor& images, const Tensor& gradImages,
                    const Tensor& gradDensity) {
  validate(settings);
  const GridSize grid = volumeGrid(density, "render density");
  requireShape(images, imageShape(views), "the forward images");
  requireShape(gradImages, imageShape(views), "the image gradient");
  if (gradDensity.numel() != density.numel())
    throw Error("render backward: the density gradient " + toString(gradDensity.shape()) +
                " must match the density " + toString(density.shape()));
  const bool lit = settings.light.has_value();
  const MarchInputs in{density, lit ? requireShadow(shadow, grid, settings) : density, views, settings, grid, images,
                       gradImages, deviceLook(stream.context(), settings), lit};
  // Without a light the density gradient is the march's own; with one the march adds into the direct part
  // and the light-transmittance gradient, which the light pass's adjoint turns into the density gradient.
  const Tensor direct = lit ? Tensor(stream.context(), grid.volume()) : gradDensity;
  const Tensor gradShadow = Tensor(stream.context(), lit ? grid.volume() : Shape{1});
  if (adjointsByPlanes(stream.context(), views))
    marchAdjointByPlanes(stream, in, direct, gradShadow);
  else
    marchAdjointScattered(stream, in, direct, gradShadow);
  if (!lit) return;
  RenderSettings withLook = settings;  // the device look the march's adjoint read, not a second upload of it
  withLook.look = in.look;
  lightTransmittanceBackward(stream, in.shadowOrDensity, gradShadow, direct, withLook, gradDensity);
}

void lightTransmittanceBackward(Stream& stream, const Tensor& shadow, const Tensor& gradShadow, const Tensor& direct,
                                const RenderSettings& settings, const Tensor& gradDensity, const Tensor* box) {
  validate(settings);
  if (!settings.light) throw Error("render: the light transmittance's adjoint needs a light in the settings");
  const GridSize grid = volumeGrid(shadow, "light transmittance");
  for (const Tensor* t : {&gradShadow, &direct, &gradDensity}) requireShape(*t, grid.volume(), "each volume of the light pass's adjoint");
  stream.dispatchFlat(stream.kernel("render/light_transmittance_adjoint", kWorkgroup),
                      {asVec4(cornerQuads(stream, shadow)), asVec4(cornerQuads(stream, gradShadow)), direct, gradDensity,
                       deviceLook(stream.context(), settings), asVec4(box ? *box : occupiedBox(stream, gradShadow))},
                      lightPush(grid, *settings.light), static_cast<uint64_t>(grid.x * grid.y * grid.z));
}

}  // namespace smokesvd::render

// The differentiable volume renderer: emission-absorption ray marching of a density volume, optionally lit
// by one directional light with self-shadowing, every view in one dispatch.
//
// Typical use (e.g. 16 orbit views of each simulated frame):
//   const auto cameras = orbitCameras(orbitAngles(16), grid, 64, 112);
//   render::ViewSet views = render::uploadViews(context, cameras);       // once
//   Tensor images(context, {16, 1, 112, 64});
//   render::render(stream, density, views, settings, images);           // density [D, H, W]
//   stream.submit();
//
// Model (docs/rendering.md), per ray with samples k at a fixed step (voxels) inside the volume:
//   a_k = 1 - exp(-absorption * density_k * step),  T_k = prod_{j<k} (1 - a_k),  image = sum_k T_k a_k S_k
// with source S_k = ambient, plus intensity * T_L(p_k) with a light, T_L being the light's transmittance
// from p_k through the volume. Density is sampled trilinearly with zero padding. Images are [V, 1, H, W],
// row 0 at the top; the background is black. Lengths are grid units (voxels).
//
// Gradients: renderBackward gives the exact d loss / d density, including the path through the shadow.
// It scatters with float atomics, or compare-and-swap loops on devices without them (render/atomics.h).
#pragma once

#include <optional>
#include <vector>

#include "pipeline/render/view_set.h"
#include "runtime/stream.h"

namespace smokesvd::render {

struct DirectionalLight {
  Vec3 direction{-0.5, 1.0, -1.0};  // toward the light, grid coordinates (normalised on use)
  float intensity = 1.0f;
  float step = 1.0f;                // light march step, voxels
  float absorption = 1.0f;          // extinction per unit density per voxel along the light path
};

struct RenderSettings {
  float step = 1.0f;        // ray march step, voxels
  float absorption = 1.0f;  // extinction per unit density per voxel
  float ambient = 1.0f;     // source radiance everywhere (the whole source without a light)
  std::optional<DirectionalLight> light;
  // The look on the device: when defined, the kernels read absorption, ambient and the light's intensity,
  // absorption and direction from this [8] tensor (lookValues' layout) instead of the fields above, so a
  // recording renders with another look after an upload (uploadLook). Steps and whether there is a light
  // (which selects the kernels) stay those of the fields.
  Tensor look;
};

// Throws Error naming the field unless steps are at least 0.001 voxels, absorptions >= 0 and every number finite.
void validate(const RenderSettings& settings);

// [absorption, ambient, light intensity, light absorption, unit light direction x, y, z, 0]; the light's
// entries are 0 without a light (shaders/render/look.glsl).
std::vector<float> lookValues(const RenderSettings& settings);
// A device look for `settings` (validated), and an upload of another look into it.
Tensor lookTensor(Context& context, const RenderSettings& settings);
void uploadLook(const Tensor& look, const RenderSettings& settings);

// Renders density [D, H, W] through every view into images [V, 1, h, w].
void render(Stream& stream, const Tensor& density, const ViewSet& views, const RenderSettings& settings,
            const Tensor& images);

// The pieces render() is made of, for callers that keep the shadow volume for the backward pass. Both take
// only the samples inside the density's occupied box (occupied_box.h; the same results bit for bit):
// `box`, where given, is occupiedBox(density), so that the two share it; null makes it here.
// lightTransmittance: T_L at every voxel centre, shadow [D, H, W]; needs settings.light.
void lightTransmittance(Stream& stream, const Tensor& density, const RenderSettings& settings, const Tensor& shadow,
                        const Tensor* box = nullptr);
// march: the camera rays; `shadow` is required with a light and ignored without.
void march(Stream& stream, const Tensor& density, const Tensor* shadow, const ViewSet& views,
           const RenderSettings& settings, const Tensor& images, const Tensor* box = nullptr);

// d loss / d density from gradImages = d loss / d images, given the forward's images (and shadow, with a
// light). Writes gradDensity [D, H, W].
void renderBackward(Stream& stream, const Tensor& density, const Tensor* shadow, const ViewSet& views,
                    const RenderSettings& settings, const Tensor& images, const Tensor& gradImages,
                    const Tensor& gradDensity);

// The light pass's adjoint, the last piece of renderBackward() with a light: gradDensity = direct + the density
// gradient that gradShadow = d loss / d shadow carries back through lightTransmittance(), all [D, H, W]. It
// takes only the samples inside gradShadow's occupied box (the same result bit for bit): `box`, where given, is
// occupiedBox(gradShadow); null makes it here.
void lightTransmittanceBackward(Stream& stream, const Tensor& shadow, const Tensor& gradShadow, const Tensor& direct,
                                const RenderSettings& settings, const Tensor& gradDensity, const Tensor* box = nullptr);

}  // namespace smokesvd::render

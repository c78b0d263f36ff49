#include "pipeline/differentiable/render.h"

#include "nets/op_registry.h"
#include "pipeline/camera/calibration.h"
#include "pipeline/render/lift.h"
#include "pipeline/render/occupied_box.h"
#include "pipeline/render/rotate.h"
#include "runtime/error.h"

namespace smokesvd::diff {

Var render(Tape& tape, const Var& density, const render::ViewSet& views, const render::RenderSettings& settings) {
  const GridSize grid = render::volumeGrid(density->value, "render density");
  Tensor images(tape.context(), {views.views, 1, views.height, views.width});
  const Tensor box = render::occupiedBox(tape.stream(), density->value);
  Tensor shadow;
  if (settings.light) {
    shadow = Tensor(tape.context(), grid.volume());
    render::lightTransmittance(tape.stream(), density->value, settings, shadow, &box);
  }
  render::march(tape.stream(), density->value, settings.light ? &shadow : nullptr, views, settings, images, &box);
  Var out = tape.output(images, {density});
  if (out->requiresGrad) {
    tape.record({out}, [density, out, views, settings, shadow](Tape& t) {
      Tensor gradDensity(t.context(), density->value.shape());
      render::renderBackward(t.stream(), density->value, settings.light ? &shadow : nullptr, views, settings,
                             out->value, t.grad(out), gradDensity);
      t.accumulate(density, gradDensity);
    });
  }
  return out;
}

Var lift(Tape& tape, const Var& images, const render::ViewSet& views, const GridSize& grid) {
  Tensor lifted(tape.context(), {1, views.views, grid.z, grid.y, grid.x});
  render::lift(tape.stream(), images->value, views, grid, lifted);
  Var out = tape.output(lifted, {images});
  if (out->requiresGrad) {
    tape.record({out}, [images, out, views, grid](Tape& t) {
      Tensor gradImages(t.context(), images->value.shape());
      render::liftBackward(t.stream(), t.grad(out), views, grid, gradImages);
      t.accumulate(images, gradImages);
    });
  }
  return out;
}

Var rotate(Tape& tape, const Var& volume, double angleDegrees) {
  Tensor rotated(tape.context(), volume->value.shape());
  render::rotate(tape.stream(), volume->value, angleDegrees, rotated);
  Var out = tape.output(rotated, {volume});
  if (out->requiresGrad) {
    tape.record({out}, [volume, out, angleDegrees](Tape& t) {
      Tensor gradVolume(t.context(), volume->value.shape());
      render::rotateBackward(t.stream(), t.grad(out), angleDegrees, gradVolume);
      t.accumulate(volume, gradVolume);
    });
  }
  return out;
}

namespace {

const std::vector<AttrSpec> kCameraAttrs{
    {"angles", "0", "orbit angles in degrees, comma-separated (ignored with cameras)"},
    {"cameras", "-", "NeRF-style calibration JSON: render through all its cameras instead of orbit ones"},
    {"width", "0", "image width in pixels (0: the grid width, or the calibrated width)"},
    {"height", "0", "orbit image height in pixels (0: the grid height)"}};

std::vector<AttrSpec> renderAttrs() {
  std::vector<AttrSpec> attrs = kCameraAttrs;
  attrs.insert(attrs.end(), {{"step", "1", "march step, voxels"},
                             {"absorption", "1", "extinction per unit density per voxel"},
                             {"ambient", "1", "source radiance without the light"},
                             {"light", "-", "direction toward a directional light x,y,z (grid axes), or - for none"},
                             {"light_intensity", "1", "light intensity"},
                             {"light_step", "1", "light march step, voxels"},
                             {"light_absorption", "1", "extinction along the light path"}});
  return attrs;
}

render::ViewSet viewsFromAttrs(Context& context, const OpAttrs& attrs, const GridSize& grid) {
  const int width = static_cast<int>(attrs.integer("width"));
  std::vector<Camera> cameras;
  if (const std::string file = attrs.text("cameras"); file != "-") {
    const Calibration calibration = readCalibration(file);
    for (const CalibratedView& view : calibration.views)
      cameras.push_back(calibratedCamera(view, calibration.box, grid, width));
  } else {
    const int height = static_cast<int>(attrs.integer("height"));
    cameras = orbitCameras(attrs.numbers("angles"), grid,
                           width > 0 ? width : static_cast<int>(grid.x),
                           height > 0 ? height : static_cast<int>(grid.y));
  }
  return render::uploadViews(context, cameras);
}

render::RenderSettings settingsFromAttrs(const OpAttrs& attrs) {
  render::RenderSettings s;
  s.step = static_cast<float>(attrs.number("step"));
  s.absorption = static_cast<float>(attrs.number("absorption"));
  s.ambient = static_cast<float>(attrs.number("ambient"));
  if (const std::string light = attrs.text("light"); light != "-") {
    const std::vector<double> d = attrs.numbers("light");
    if (d.size() != 3) throw Error("op render: attribute light must be three numbers x,y,z");
    render::DirectionalLight l;
    l.direction = {d[0], d[1], d[2]};
    l.intensity = static_cast<float>(attrs.number("light_intensity"));
    l.step = static_cast<float>(attrs.number("light_step"));
    l.absorption = static_cast<float>(attrs.number("light_absorption"));
    s.light = l;
  }
  render::validate(s);
  return s;
}

GridSize gridAttr(const OpAttrs& attrs) {
  const std::vector<int64_t> g = attrs.integers("grid");
  if (g.size() != 3 || g[0] <= 0 || g[1] <= 0 || g[2] <= 0)
    throw Error("op lift: attribute grid must be D,H,W (three positive integers)");
  return {.x = g[2], .y = g[1], .z = g[0]};
}

std::vector<AttrSpec> liftAttrs() {
  std::vector<AttrSpec> attrs = kCameraAttrs;
  attrs.push_back({"grid", "", "volume size D,H,W"});
  return attrs;
}

// Densities kept positive under the finite-difference steps.
InputDraw densityDraw(Shape shape) { return draw::uniform(std::move(shape), 0.05f, 1.0f); }

// The scatter kernels add in any order on GPUs (render/atomics.h): gradients agree to float rounding there.
constexpr double kScatterRepeat = 1e-5;

// Orbit views with the volume's height in pixels run their adjoints by voxel planes on CPU devices
// (ViewSet::raysInVoxelRows); views of another height scatter with atomics everywhere.
std::vector<OpExample> renderExamples() {
  return {{.name = "two orbit views, one pixel row per voxel row, no light",
           .inputs = {{"density", densityDraw({5, 6, 7})}},
           .attrs = {{"angles", "0,90"}, {"absorption", "0.7"}},
           .repeatTolerance = kScatterRepeat},
          {.name = "one view at 30 degrees, other image size, directional light",
           .inputs = {{"density", densityDraw({4, 5, 6})}},
           .attrs = {{"angles", "30"}, {"width", "9"}, {"height", "7"}, {"light", "0.3,1,-0.4"}, {"ambient", "0.4"},
                     {"light_intensity", "0.8"}, {"step", "0.7"}},
           .repeatTolerance = kScatterRepeat},
          {.name = "light, other image size, compare-and-swap scatter",
           .inputs = {{"density", densityDraw({4, 5, 6})}},
           .attrs = {{"angles", "-20,60"}, {"height", "4"}, {"light", "-0.5,1,0.5"}, {"light_absorption", "0.5"}},
           .repeatTolerance = kScatterRepeat,
           .noFloatAtomics = true},
          {.name = "three orbit views, one pixel row per voxel row, directional light",
           .inputs = {{"density", densityDraw({4, 5, 6})}},
           .attrs = {{"angles", "-20,60,200"}, {"width", "7"}, {"light", "-0.5,1,0.5"}, {"light_absorption", "0.5"}},
           .repeatTolerance = kScatterRepeat}};
}

std::vector<OpExample> liftExamples() {
  return {{.name = "two orbit views, one pixel row per voxel row",
           .inputs = {{"images", draw::uniform({2, 1, 5, 7})}},
           .attrs = {{"angles", "0,90"}, {"grid", "4,5,7"}},
           .gradient = {.step = 0.25},
           .repeatTolerance = kScatterRepeat},
          {.name = "two views of another height",
           .inputs = {{"images", draw::uniform({2, 1, 3, 7})}},
           .attrs = {{"angles", "20,110"}, {"grid", "4,5,7"}, {"height", "3"}},
           .gradient = {.step = 0.25},
           .repeatTolerance = kScatterRepeat},
          {.name = "three views of another size, compare-and-swap scatter",
           .inputs = {{"images", draw::uniform({3, 1, 3, 6})}},
           .attrs = {{"angles", "15,75,135"}, {"grid", "5,4,5"}, {"width", "6"}, {"height", "3"}},
           .gradient = {.step = 0.25},
           .repeatTolerance = kScatterRepeat,
           .noFloatAtomics = true}};
}

const bool registered =
    registerOp({"render", "emission-absorption rendering of density [D,H,W] to images [V,1,h,w]", {"density"}, {},
                renderAttrs(), {"images"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  const GridSize grid = render::volumeGrid(in[0]->value, "op render: density");
                  return std::vector<Var>{
                      render(t, in[0], viewsFromAttrs(t.context(), attrs, grid), settingsFromAttrs(attrs))};
                },
                renderExamples()}) &&
    registerOp({"lift", "images [V,1,h,w] spread along camera rays into [1,V,D,H,W]", {"images"}, {}, liftAttrs(),
                {"lifted"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  const GridSize grid = gridAttr(attrs);
                  return std::vector<Var>{lift(t, in[0], viewsFromAttrs(t.context(), attrs, grid), grid)};
                },
                liftExamples()}) &&
    registerOp({"rotate", "volume [...,D,H,W] turned about the vertical axis by angle degrees", {"x"}, {},
                {{"angle", "", "degrees"}}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return std::vector<Var>{rotate(t, in[0], attrs.number("angle"))};
                },
                {{.name = "one volume, 30 degrees", .inputs = {{"x", draw::uniform({5, 6, 7})}}, .attrs = {{"angle", "30"}},
                  .gradient = {.step = 0.25}},
                 {.name = "channels of volumes, -90 degrees",
                  .inputs = {{"x", draw::uniform({2, 3, 4, 5, 4})}},
                  .attrs = {{"angle", "-90"}},
                  .gradient = {.step = 0.25}}}});

}  // namespace
}  // namespace smokesvd::diff

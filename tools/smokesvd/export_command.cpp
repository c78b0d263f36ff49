// `smokesvd export RUN_DIR --out DIR (--vdb | --nerf | --mantaflow)`: a reconstruction, re-simulation or
// simulation written for other tools (docs/applications.md):
//
//   smokesvd export recon/ --out vdb/ --vdb --z-up          OpenVDB per frame for Blender (z up) or Houdini (y up)
//   smokesvd export recon/ --out nerf/ --nerf               per-frame NeRF / 3D Gaussian Splatting datasets
//   smokesvd export recon/ --out manta/ --mantaflow         mantaflow's .npz grids, to continue there
#include <iostream>

#include "pipeline/export/export_run.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"

namespace smokesvd::cli {
namespace {

struct ExportArguments {
  std::string source, out, calibration;
  bool vdb = false, nerf = false, mantaflow = false, zUp = false, overwrite = false;
  double cameraError = 0.25;
};

void runExportCommand(const ExportArguments& a) {
  exporters::ExportOptions o;
  o.source = a.source;
  o.out = a.out;
  o.format = a.vdb ? exporters::Format::Vdb : a.nerf ? exporters::Format::Nerf : exporters::Format::Mantaflow;
  if (!a.calibration.empty()) o.calibration = a.calibration;
  o.zUp = a.zUp;
  o.cameraError = a.cameraError;
  o.overwrite = a.overwrite;
  const exporters::ExportResult r = exporters::runExport(o);
  std::cerr << a.out << ": " << r.frames << " frames (" << r.index.string() << " says what is where)\n";
}

void addExportCommand(CLI::App& app, const GlobalOptions&, Action& action) {
  static ExportArguments a;
  CLI::App* c = app.add_subcommand(
      "export", "write a reconstruction, re-simulation or simulation for Blender, Houdini, NeRF/3DGS tools or mantaflow");
  c->add_option("run", a.source, "a folder written by smokesvd reconstruct, resim or simulate")->required();
  c->add_option("--out", a.out, "output folder")->required();
  CLI::Option* vdb = c->add_flag("--vdb", a.vdb,
              std::string("OpenVDB files per frame: float grid density, vec3s grid velocity (world units per second)") +
                  (exporters::openVdbAvailable() ? "" : " [not in this build: no OpenVDB]"));
  CLI::Option* nerf = c->add_flag("--nerf", a.nerf, "per-frame folders of the 16 views with NeRF/nerfstudio transforms.json");
  CLI::Option* mantaflow = c->add_flag("--mantaflow", a.mantaflow, "mantaflow's .npz grids (arr_0; density [z,y,x,1], MAC velocity [z,y,x,3], flags)");
  c->add_option("--calibration", a.calibration, "info.json that placed the box in the world (default: the one the run records)");
  c->add_flag("--z-up", a.zUp, "a z-up world (Blender) instead of y up (Houdini, the calibration's world)");
  c->add_option("--camera-error", a.cameraError,
                "--nerf: the largest error of the pinhole stand-ins for the orthographic views, pixels (default 0.25)")
      ->check(positiveNumber(100))
      ->needs(nerf);
  c->add_flag("--overwrite", a.overwrite, "replace an export in --out");
  // One format per run.
  vdb->excludes(nerf)->excludes(mantaflow);
  nerf->excludes(mantaflow);
  c->callback([&action, vdb, nerf, mantaflow] {
    if (vdb->count() + nerf->count() + mantaflow->count() == 0)
      throw CLI::RequiredError("give one of --vdb, --nerf, --mantaflow", CLI::ExitCodes::RequiredError);
    action = [] { runExportCommand(a); };
  });
}

const bool registered = registerCommand({"export", addExportCommand});

}  // namespace
}  // namespace smokesvd::cli

// `smokesvd demo [--out DIR]`: the method end to end on a held-out simulated plume, with the shipped
// weights, against two baselines (pipeline/reconstruct/demo.h). The README's first command.
#include <iostream>

#include "pipeline/reconstruct/demo.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"

namespace smokesvd::cli {
namespace {

void addDemoCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static reconstruct::DemoOptions o;
  static std::string out = "smokesvd-demo", models;
  CLI::App* c = app.add_subcommand("demo", "simulate a held-out plume, reconstruct its front-view video, compare with the truth");
  c->add_option("--out", out, "output folder (default smokesvd-demo)");
  c->add_option("--models", models, "folder of trained networks (default: the shipped models/small)");
  c->add_option("--frames", o.frames, "frames of the plume (default 40)")->check(wholeNumber(2, 1000));
  c->callback([&global, &action] {
    action = [&global] {
      o.out = out;
      o.models = models;
      Context context(global.contextOptions());
      std::cout << reconstruct::runDemo(context, o);
    };
  });
}

const bool registered = registerCommand({"demo", addDemoCommand});

}  // namespace
}  // namespace smokesvd::cli

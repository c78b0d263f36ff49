// `smokesvd op`: runs any registered op forward (and backward when upstream gradients are given) on
// .npy files, so each kernel can be checked or timed against another framework.
//
//   smokesvd op --list
//   smokesvd op conv2d --in x=x.npy --in w=w.npy --attr stride=2 --out y=y.npy
//   smokesvd op conv2d ... --in grad_y=gy.npy --out grad_x=gx.npy --out grad_w=gw.npy
#include <iostream>
#include <map>

#include "nets/io/finite_values.h"
#include "nets/io/npy.h"
#include "nets/op_registry.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"

namespace smokesvd::cli {
namespace {

struct OpArguments {
  std::string name;
  bool list = false;
  std::vector<std::string> inputs, attrs, outputs;
};

std::map<std::string, std::string> keyValues(const std::vector<std::string>& items, const std::string& flag) {
  std::map<std::string, std::string> result;
  for (const std::string& item : items) {
    const std::size_t equals = item.find('=');
    if (equals == std::string::npos || equals == 0 || equals + 1 == item.size())
      throw Error(flag + " '" + item + "': expected NAME=VALUE");
    if (!result.emplace(item.substr(0, equals), item.substr(equals + 1)).second)
      throw Error(flag + " '" + item.substr(0, equals) + "' is given twice");
  }
  return result;
}

std::string joined(const std::vector<std::string>& names, const std::string& prefix = "") {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + prefix + name;
  return text.empty() ? "-" : text;
}

void printCatalogue() {
  for (const OpSpec& spec : registeredOps()) {
    std::string attrs;
    for (const AttrSpec& attr : spec.attrs)
      attrs += (attrs.empty() ? "" : ", ") + attr.name + (attr.defaultValue.empty() ? "" : "=" + attr.defaultValue);
    std::cout << spec.name << ": " << spec.summary << "\n"
              << "    inputs: " << joined(spec.inputs)
              << (spec.optionalInputs.empty() ? "" : " [optional: " + joined(spec.optionalInputs) + "]") << "\n"
              << "    attrs: " << (attrs.empty() ? "-" : attrs) << "\n"
              << "    outputs: " << joined(spec.outputs) << "\n";
  }
}

Tensor load(Context& context, const std::string& path) {
  const io::NpyArray array = io::readNpy(path);
  const std::vector<float> values = array.toFloat();
  io::requireFiniteValues(values, array.shape, path, "op inputs");
  return Tensor::fromHost(context, array.shape, values);
}

void runOp(const GlobalOptions& global, const OpArguments& args) {
  const OpSpec& spec = findOp(args.name);
  std::map<std::string, std::string> inputFiles = keyValues(args.inputs, "--in");
  const std::map<std::string, std::string> outputFiles = keyValues(args.outputs, "--out");
  const OpAttrs attrs = resolveAttrs(spec, keyValues(args.attrs, "--attr"));

  std::map<std::string, std::string> seedFiles;
  for (const std::string& output : spec.outputs) {
    auto seed = inputFiles.find("grad_" + output);
    if (seed == inputFiles.end()) continue;
    seedFiles[output] = seed->second;
    inputFiles.erase(seed);
  }
  const bool differentiate = !seedFiles.empty();

  Context context(global.contextOptions());
  Stream stream(context);
  Tape tape(stream);
  std::vector<std::string> names = spec.inputs;
  names.insert(names.end(), spec.optionalInputs.begin(), spec.optionalInputs.end());
  std::vector<Var> inputs;
  for (std::size_t i = 0; i < names.size(); ++i) {
    auto file = inputFiles.find(names[i]);
    if (file == inputFiles.end()) {
      if (i < spec.inputs.size())
        throw Error("op " + spec.name + ": input '" + names[i] + "' is missing (--in " + names[i] + "=FILE.npy)");
      inputs.push_back(nullptr);
      continue;
    }
    inputs.push_back(variable(load(context, file->second), differentiate, names[i]));
    inputFiles.erase(file);
  }
  if (!inputFiles.empty())
    throw Error("op " + spec.name + " has no input '" + inputFiles.begin()->first + "' (inputs: " + joined(names) +
                "; upstream gradients: " + joined(spec.outputs, "grad_") + ")");

  const std::vector<Var> outputs = spec.apply(tape, inputs, attrs);
  std::map<std::string, Var> byName;
  for (std::size_t i = 0; i < outputs.size() && i < spec.outputs.size(); ++i) byName[spec.outputs[i]] = outputs[i];
  if (differentiate) {
    std::vector<std::pair<Var, Tensor>> seeds;
    for (const auto& [output, path] : seedFiles) {
      Tensor seed = load(context, path);
      if (seed.shape() != byName.at(output)->value.shape())
        throw Error(path + ": grad_" + output + " has shape " + toString(seed.shape()) + ", expected " +
                    toString(byName.at(output)->value.shape()));
      seeds.emplace_back(byName.at(output), seed);
    }
    tape.backward(seeds);
  }
  stream.submit();

  for (const auto& [name, path] : outputFiles) {
    Tensor result;
    if (byName.count(name)) {
      result = byName[name]->value;
    } else if (name.starts_with("grad_")) {
      const auto input = std::find(names.begin(), names.end(), name.substr(5));
      if (input == names.end() || !differentiate)
        throw Error("op " + spec.name + ": cannot write '" + name + "': " +
                    (differentiate ? "no such input" : "give an upstream gradient (--in grad_OUTPUT=FILE) first"));
      const Var& var = inputs[static_cast<std::size_t>(input - names.begin())];
      if (!var) throw Error("op " + spec.name + ": input '" + *input + "' was not given");
      result = var->grad.defined() ? var->grad : Tensor::fromHost(context, var->value.shape(),
                                                                   std::vector<float>(var->value.numel(), 0.0f));
    } else {
      throw Error("op " + spec.name + " has no output '" + name + "' (outputs: " + joined(spec.outputs) +
                  "; input gradients: " + joined(names, "grad_") + ")");
    }
    io::writeNpy(path, io::NpyArray::fromFloats(result.shape(), result.download()));
  }
}

void addOpCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static OpArguments args;
  CLI::App* command = app.add_subcommand("op", "run one op forward (and backward) on .npy files");
  command->add_option("name", args.name, "the op to run (see --list)");
  command->add_flag("--list", args.list, "list every op with its inputs, attributes and outputs");
  command->add_option("--in", args.inputs, "NAME=FILE.npy: an input, or grad_OUTPUT=FILE.npy: an upstream gradient");
  command->add_option("--attr", args.attrs, "NAME=VALUE: an attribute");
  command->add_option("--out", args.outputs, "NAME=FILE.npy: an output, or grad_INPUT=FILE.npy: an input's gradient");
  command->callback([&global, &action] {
    action = [&global] {
      if (args.list) return printCatalogue();
      if (args.name.empty()) throw Error("op: name an op to run, or --list");
      runOp(global, args);
    };
  });
}

const bool registered = registerCommand({"op", addOpCommand});

}  // namespace
}  // namespace smokesvd::cli

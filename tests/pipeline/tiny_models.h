// A tiny-preset dataset and the six networks of the method trained on it for a few steps, made once per
// build and shared by every test process: cached under the build folder, keyed by the test program's
// build time, and guarded by a file lock so that parallel ctest processes make it once.
#pragma once

#include <filesystem>

namespace smokesvd::testing {

const std::filesystem::path& tinyDataset();  // scene_0000 .. scene_0003, 8 frames each, no renders
const std::filesystem::path& tinyModels();   // <network>/{config.json, model.safetensors}
// A fresh folder for one test inside this program's temporary folder (removed first if it exists; all of them
// when the program ends).
std::filesystem::path tinyScratch(const std::string& name);

}  // namespace smokesvd::testing

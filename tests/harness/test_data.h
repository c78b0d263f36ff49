// Reference files the tests read: those kept in the repository under tests/data/ (tests/data/README.md
// says where each comes from), and the real ScalarFlow footage, which is not in the repository.
#pragma once

#include <filesystem>
#include <string>

namespace smokesvd::testing {

// tests/data/<name> in the source tree, e.g. testData("mantaflow/advect_32x48x32.npz").
std::filesystem::path testData(const std::string& name);

// The ScalarFlow footage folder (info.json and train00..04.mp4): $SMOKESVD_SCALARFLOW_DATA, else
// ../shared/data/scalarflow_real beside the checkout. Tests that need it skip when it is absent.
std::filesystem::path scalarflowFolder();

}  // namespace smokesvd::testing

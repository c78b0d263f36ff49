#include "tests/harness/test_data.h"

#include <cstdlib>

namespace smokesvd::testing {

std::filesystem::path testData(const std::string& name) {
  return std::filesystem::path(SMOKESVD_SOURCE_DIR) / "tests" / "data" / name;
}

std::filesystem::path scalarflowFolder() {
  if (const char* folder = std::getenv("SMOKESVD_SCALARFLOW_DATA")) return folder;
  return std::filesystem::path(SMOKESVD_SOURCE_DIR) / ".." / "shared" / "data" / "scalarflow_real";
}

}  // namespace smokesvd::testing

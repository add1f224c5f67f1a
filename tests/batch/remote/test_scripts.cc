#include "tests/batch/remote/test_scripts.h"

namespace tavis::batch::remote::testing {

std::string TestScript(const std::string& name) { return std::string(TAVIS_TEST_DATA_DIR) + "/" + name; }

}  // namespace tavis::batch::remote::testing

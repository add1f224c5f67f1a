// Test support: the Python counterparts in this folder (policy_server.py, golden_msgpack.py),
// run with Debian's /usr/bin/python3 through tests/support/child_process.h.
#pragma once

#include <string>

#include "tests/support/child_process.h"

namespace tavis::batch::remote::testing {

inline constexpr const char* kPythonHint = "are python3-msgpack, python3-numpy and python3-websockets installed?";

// The path of a script in this test folder.
std::string TestScript(const std::string& name);

using tavis::testing::FreeLoopbackPort;

}  // namespace tavis::batch::remote::testing

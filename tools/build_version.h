// The program's version, recorded when it was built: "0.1.0 (git v0.1-12-gabc1234-dirty)"
// (cmake/WriteBuildVersion.cmake; "git unknown" when built outside a git checkout).
#pragma once

namespace tavis::tools {

const char* BuildVersion();

}  // namespace tavis::tools

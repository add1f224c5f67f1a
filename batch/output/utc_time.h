// The wall-clock time result folders record (a lock's holder, a sweep's manifest timing).
#pragma once

#include <string>

namespace tavis::batch::output {

// Now in UTC, ISO 8601 to the second: "2026-11-27T08:38:36Z".
std::string UtcNow();

}  // namespace tavis::batch::output

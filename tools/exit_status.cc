#include "tools/exit_status.h"

namespace tavis::tools {
namespace {

int usage_error_status = 1;

}  // namespace

void SetUsageErrorStatus(int status) { usage_error_status = status; }

int UsageErrorStatus() { return usage_error_status; }

}  // namespace tavis::tools

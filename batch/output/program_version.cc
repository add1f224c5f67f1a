#include "batch/output/program_version.h"

#ifndef TAVIS_VERSION
#define TAVIS_VERSION "unknown"
#endif

namespace tavis::batch::output {

std::string ProgramVersion() { return TAVIS_VERSION; }

}  // namespace tavis::batch::output

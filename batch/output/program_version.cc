#include "batch/output/program_version.h"

#ifndef TAVIS_VERSION
#define TAVIS_VERSION "unknown"
#endif
#ifndef TAVIS_REVISION
#define TAVIS_REVISION "unknown"
#endif

namespace tavis::batch::output {

std::string ProgramVersion() { return TAVIS_VERSION; }

std::string ProgramRevision() { return TAVIS_REVISION; }

}  // namespace tavis::batch::output

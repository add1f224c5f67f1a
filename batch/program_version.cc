#include "batch/program_version.h"

#ifndef TAVIS_VERSION
#define TAVIS_VERSION "unknown"
#endif

namespace tavis::batch {

std::string ProgramVersion() { return TAVIS_VERSION; }

}  // namespace tavis::batch

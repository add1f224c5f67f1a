// The program's version, recorded in every result folder and compared by resumes and merges.
#pragma once

#include <string>

namespace tavis::batch::output {

// `git describe --always --tags --dirty` of the source tree the program was configured from
// ("unknown" outside a git checkout).
std::string ProgramVersion();

// The full commit hash (`git rev-parse HEAD`) of that source tree ("unknown" outside a git
// checkout): what ProgramVersion's short hash abbreviates, for a provenance record.
std::string ProgramRevision();

}  // namespace tavis::batch::output

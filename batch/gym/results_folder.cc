#include "batch/gym/results_folder.h"

#include <stdexcept>
#include <string>

#include "batch/output/output_folder.h"

namespace tavis::batch::gym {

void WriteResultsFolder(const cell::CellResult& result, const cell::RunInfo& info, const std::filesystem::path& out,
                        bool overwrite) {
  constexpr output::OutputKind kCell = output::OutputKind::kEvalCell;
  output::RequireUsableOutputPath(out, "out_dir");
  // Locked before it is looked at, so that what is checked is what this process then writes: a
  // `tavis eval` still running there is refused here, whatever the folder holds.
  const output::OutputLock lock = output::CreateAndLockOutput(out, kWriteResultsCommand);
  if (output::HoldsNoResults(out)) {
    output::WriteOutputMarker(out, kCell);
    cell::WriteCellReport(result, info, out.string());
    return;
  }
  if (!overwrite) {
    throw std::invalid_argument("out_dir " + out.string() +
                                " already holds results; give overwrite=True to replace them, or another out_dir");
  }
  output::RequireEmptyOrOwn(out, kCell,
                            "overwrite=True replaces only a cell tavis wrote: move those files away or give another "
                            "out_dir");
  output::OutputReplacement replacement(out, kWriteResultsCommand);
  output::WriteOutputMarker(replacement.staging(), kCell);
  cell::WriteCellReport(result, info, replacement.staging().string());
  replacement.SwapIn();
}

}  // namespace tavis::batch::gym

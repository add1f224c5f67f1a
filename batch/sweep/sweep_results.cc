#include "batch/sweep/sweep_results.h"

#include <stdexcept>

#include "batch/atomic_file.h"
#include "batch/report/html_report.h"
#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"
#include "batch/sweep/sweep_cell.h"

namespace tavis::batch::sweep {

void WriteSweepResults(const std::filesystem::path& dir, const nlohmann::ordered_json& spec_json,
                       const std::vector<SweepCell>& cells, const nlohmann::ordered_json& manifest) {
  std::vector<report::CellEpisodes> episodes;
  for (const SweepCell& cell : cells) {
    std::optional<std::vector<EpisodeRecord>> records = ReadCompleteCell(dir / "cells" / cell.id, cell.config);
    if (!records) throw std::runtime_error((dir / "cells" / cell.id).string() + " is not a complete cell of this sweep");
    episodes.push_back({cell.id, cell.config, std::move(*records)});
  }
  const nlohmann::ordered_json summary = report::SweepSummaryJson(spec_json, episodes);
  WriteFileAtomically(dir / "summary.json", summary.dump(2) + "\n");
  std::filesystem::create_directories(dir / "tables");
  for (const report::TextTable& table : report::SweepTables(summary)) {
    WriteFileAtomically(dir / "tables" / (table.name + ".md"), report::ToMarkdown(table));
    WriteFileAtomically(dir / "tables" / (table.name + ".csv"), report::ToCsv(table));
    WriteFileAtomically(dir / "tables" / (table.name + ".tex"), report::ToLatex(table));
  }
  WriteFileAtomically(dir / "report.html", report::SweepHtmlReport(summary, manifest));
}

}  // namespace tavis::batch::sweep

#include "batch/sweep/sweep_results.h"

#include <fstream>
#include <stdexcept>

#include "batch/output/atomic_file.h"
#include "batch/report/figure_drawing.h"
#include "batch/report/gaze_figures.h"
#include "batch/report/html_report.h"
#include "batch/report/paper_table.h"
#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"
#include "batch/sweep/galt_reference.h"
#include "batch/sweep/sequential_plan.h"
#include "batch/sweep/sweep_cell.h"

namespace tavis::batch::sweep {
namespace {

// What the cell's servers reported (summary.json's server_metadata; empty for built-in policies).
nlohmann::ordered_json ServerMetadata(const std::filesystem::path& cell_dir) {
  std::ifstream in(cell_dir / "summary.json");
  const nlohmann::ordered_json summary = nlohmann::ordered_json::parse(in, nullptr, false);
  if (summary.is_object() && summary.contains("server_metadata")) return summary["server_metadata"];
  return nlohmann::ordered_json::array();
}

}  // namespace

void WriteSweepResults(const std::filesystem::path& dir, const nlohmann::ordered_json& spec_json,
                       const std::vector<SweepCell>& cells, const std::vector<nlohmann::json>& cell_jsons,
                       const nlohmann::ordered_json& manifest) {
  std::vector<std::vector<cell::EpisodeRecord>> records;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::filesystem::path cell_dir = dir / "cells" / cells[i].id;
    std::optional<std::vector<cell::EpisodeRecord>> cell_records =
        ReadCompleteCell(cell_dir, cell_jsons.at(i), cells[i].config.episodes);
    if (!cell_records) throw std::runtime_error(cell_dir.string() + " is not a complete cell of this sweep");
    records.push_back(std::move(*cell_records));
  }
  // Cells stopped early by the sequential test hold what the test over their records says.
  const report::SequentialSettings sequential =
      report::SequentialSettingsFromJson(spec_json.value("sequential", nlohmann::ordered_json()));
  if (sequential.enabled) RequireSequentialStops(PlanSequential(cells, sequential), cells, records, sequential.test);
  std::vector<report::CellEpisodes> episodes;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const SweepCell& cell = cells[i];
    episodes.push_back({cell.id, cell.config, std::move(records[i]), cell.label, cell.seed_group,
                        ServerMetadata(dir / "cells" / cell.id)});
  }
  const nlohmann::ordered_json summary = report::SweepSummaryJson(
      spec_json, episodes, DatasetGaltReference(spec_json.value("figures", nlohmann::ordered_json::object())));
  output::WriteFileAtomically(dir / "summary.json", summary.dump(2) + "\n");
  std::filesystem::create_directories(dir / "tables");
  for (const report::TextTable& table : report::SweepTables(summary)) {
    output::WriteFileAtomically(dir / "tables" / (table.name + ".md"), report::ToMarkdown(table));
    output::WriteFileAtomically(dir / "tables" / (table.name + ".csv"), report::ToCsv(table));
    output::WriteFileAtomically(dir / "tables" / (table.name + ".tex"), report::ToLatex(table));
  }
  for (const nlohmann::ordered_json& label : summary["labels"]) {
    const std::string name = label["label"];
    output::WriteFileAtomically(dir / "tables" / ("table1_" + name + ".tex"), report::PaperTable1Latex(summary, name));
  }
  std::filesystem::create_directories(dir / "figures");
  std::vector<report::Figure> figures = report::DrawPaperFigures(summary["figures"]);
  for (report::Figure& figure : report::DrawGazeFigures(summary.value("gaze_figures", nlohmann::ordered_json())))
    figures.push_back(std::move(figure));
  for (const report::Figure& figure : figures) {
    output::WriteFileAtomically(dir / "figures" / (figure.name + ".svg"), figure.canvas.Svg(figure.name));
    output::WriteFileAtomically(dir / "figures" / (figure.name + ".png"), figure.canvas.Png());
  }
  output::WriteFileAtomically(dir / "report.html", report::SweepHtmlReport(summary, manifest));
}

}  // namespace tavis::batch::sweep

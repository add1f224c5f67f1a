#include "batch/report/sweep_tables.h"

#include <cstdio>
#include <sstream>
#include <utility>

#include "batch/report/camera_set_pairs.h"
#include "batch/report/failure_event_section.h"
#include "batch/report/gaze_section.h"
#include "batch/report/perturbation_pairs.h"
#include "batch/report/sequential_section.h"
#include "batch/report/stage_funnel_section.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

std::string ColumnLabel(const Json& column) {
  return column["robot"].get<std::string>() + " " + column["split"].get<std::string>() + " " +
         column["camera"].get<std::string>();
}

std::string RateText(const Json& rate) {
  if (!rate.contains("success_rate")) return "-";
  return Percent(rate["success_rate"]) + " " + PercentInterval(rate["ci_low"], rate["ci_high"]);
}

TextTable SuccessTable(const Json& suite, bool several_labels) {
  const std::string label = suite["label"];
  TextTable table{"success_" + suite["suite"].get<std::string>() + (several_labels ? "_" + label : ""),
                  suite["title"].get<std::string>() + ", " + label + ": success rate (%) [95% Wilson interval]",
                  {"task"},
                  {},
                  ""};
  const Json& columns = suite["columns"];
  const Json& differences = suite["id_minus_ood"];
  for (const Json& column : columns) table.header.push_back(ColumnLabel(column));
  for (const Json& difference : differences) {
    table.header.push_back(difference["robot"].get<std::string>() + " " + difference["camera"].get<std::string>() +
                           " id - " + difference["ood_split"].get<std::string>());
  }
  const auto points = [](const Json& value) { return value.is_null() ? std::string("-") : Points(value); };
  for (std::size_t t = 0; t < columns[0]["tasks"].size(); ++t) {
    std::vector<std::string> row{columns[0]["tasks"][t]["task"]};
    for (const Json& column : columns) row.push_back(RateText(column["tasks"][t]));
    for (const Json& difference : differences) row.push_back(points(difference["tasks"][t]));
    table.rows.push_back(row);
  }
  std::vector<std::string> average{suite["title"].get<std::string>() + " mean (task average)"};
  std::vector<std::string> pooled{suite["title"].get<std::string>() + " mean (pooled over episodes)"};
  for (const Json& column : columns) {
    average.push_back(Percent(column["task_average"]));
    pooled.push_back(RateText(column["pooled"]));
  }
  for (const Json& difference : differences) {
    average.push_back(points(difference["task_average"]));
    pooled.push_back(points(difference["pooled"]));
  }
  table.rows.push_back(average);
  table.rows.push_back(pooled);
  table.note = "Policy " + label +
               ". Cells of several evaluation seeds are pooled; other policies never are. The task average is the mean "
               "of the task rates present in the column. "
               "id - ood columns: the id rate minus the ood split's, in percentage points.";
  return table;
}

TextTable IdMinusOodTable(const Json& summary) {
  TextTable table{"id_minus_ood",
                  "id - ood: success-rate drop from the id split (percentage points)",
                  {"policy", "task", "robot", "camera", "ood split", "id %", "ood %", "id - ood"},
                  {},
                  ""};
  for (const Json& row : summary["id_minus_ood"]) {
    table.rows.push_back({row["label"], row["task"], row["robot"], row["camera"], row["ood_split"],
                          Percent(row["id_rate"]), Percent(row["ood_rate"]), Points(row["difference"])});
  }
  table.note = "Positive: the policy does worse out of distribution.";
  return table;
}

TextTable PairedTable(const Json& summary) {
  TextTable table{"head_vs_fixed",
                  "Head vs fixed camera on matched episodes",
                  {"policy", "task", "robot", "split", "pairs", "head %", "fixed %", "head - fixed", "head only",
                   "fixed only", "McNemar p"},
                  {},
                  ""};
  for (const Json& row : summary["paired"]) {
    table.rows.push_back({row["label"], row["task"], row["robot"], row["split"],
                          std::to_string(row["pairs"].get<int64_t>()), Percent(row["head_rate"]),
                          Percent(row["fixed_rate"]), Points(row["difference"]),
                          std::to_string(row["head_only"].get<int64_t>()),
                          std::to_string(row["fixed_only"].get<int64_t>()), PValue(row["mcnemar_p"])});
  }
  table.note =
      "Episode i of a cell has the same scene (seed, episode index) under both protocols, so the episodes pair: "
      "McNemar's exact two-sided test on the discordant pairs (head only vs fixed only). "
      "With the scripted expert, fixed is a sanity row: its neck is zeroed.";
  return table;
}

TextTable LengthTable(const Json& summary) {
  TextTable table{"successful_length",
                  "Length of successful episodes (s, 20 Hz steps / 20)",
                  {"policy", "task", "robot", "split", "camera", "successful", "mean s", "std s", "median s"},
                  {},
                  ""};
  for (const Json& row : summary["successful_length"]) {
    const Json& spread = row["successful_length_s"];
    table.rows.push_back({row["label"], row["task"], row["robot"], row["split"], row["camera"],
                          std::to_string(spread["n"].get<int64_t>()), Seconds(spread["mean"]), Seconds(spread["std"]),
                          Seconds(spread["median"])});
  }
  table.note = "std is the population standard deviation over the successful episodes.";
  return table;
}

TextTable GaltTable(const Json& summary) {
  TextTable table{"galt",
                  "GALT per robot and task (head camera, successful episodes)",
                  {"policy", "robot", "task", "split", "episodes", "detected", "mean s", "median s", "std s"},
                  {},
                  ""};
  for (const Json& row : summary["galt"]) {
    const std::string detected =
        std::to_string(row["n_valid"].get<int64_t>()) + " (" + Percent(row["detection_rate"]) + " %)";
    table.rows.push_back({row["label"], row["robot"], row["task"], row["split"],
                          std::to_string(row["n_episodes"].get<int64_t>()), detected, Seconds(row["mean_s"]),
                          Seconds(row["median_s"]), Seconds(row["std_s"])});
  }
  table.note = "Human teleoperation references: 2.57 s (GR1T2), 2.10 s (Reachy2).";
  return table;
}

TextTable SeedGroupTable(const Json& summary) {
  TextTable table{
      "seed_groups",
      "Seed groups: success rate (%) across checkpoints (training seeds of one recipe)",
      {"seed group", "suite", "task", "robot", "split", "camera", "checkpoints", "mean %", "std", "min %", "max %"},
      {},
      ""};
  for (const Json& group : summary["seed_groups"]) {
    const auto add = [&](const Json& row, const std::string& task) {
      table.rows.push_back({group["seed_group"], row["suite"], task, row["robot"], row["split"], row["camera"],
                            std::to_string(row["n"].get<int64_t>()), Percent(row["mean"]), Percent(row["std"]),
                            Percent(row["min"]), Percent(row["max"])});
    };
    for (const Json& row : group["rows"]) add(row, row["task"]);
    for (const Json& row : group["suite_means"]) add(row, "suite mean (task average)");
  }
  table.note =
      "Each checkpoint's rate pools its evaluation seeds; the checkpoints are not pooled: mean and sample standard "
      "deviation (n - 1) across them, in percent.";
  return table;
}

TextTable HeadlineTable(const Json& summary) {
  TextTable table{
      "headline", "Headline numbers (suite means averaged over robots, %)", {"question", "what", "value %"}, {}, ""};
  const Json& headline = summary["headline"];
  const auto value = [](const Json& number) { return number.is_null() ? std::string("-") : Percent(number); };
  if (!headline["q1_ablation"].is_null()) {
    for (const auto& [arm, number] : headline["q1_ablation"].items())
      table.rows.push_back({"Q1 ablation (Fig. 3d)", arm, value(number)});
  }
  if (!headline["q2_single_vs_multi"].is_null()) {
    for (const Json& row : headline["q2_single_vs_multi"]) {
      for (const char* which : {"single", "multi"}) {
        table.rows.push_back(
            {"Q2 single vs multi-task (Fig. 3b)", row["suite"].get<std::string>() + " " + which, value(row[which])});
      }
    }
  }
  if (!headline["q3_splits"].is_null()) {
    for (const Json& row : headline["q3_splits"]) {
      for (const char* split : {"id", "ood-spatial", "ood-init-pose"}) {
        table.rows.push_back(
            {"Q3 generalisation (Fig. 3c)", row["suite"].get<std::string>() + " " + split, value(row[split])});
      }
    }
  }
  table.note =
      "Paper (multi-task pi0): Q1 no-AV 26.6, full AV 45.9, wrist-only 63.0; Q2 TAVIS-Head 32.7 -> 43.0, TAVIS-Hands "
      "53.5 -> 73.4; Q3 TAVIS-Head 43.0 / 25.0 / 6.6, TAVIS-Hands 73.4 / 50.0 / 26.4.";
  return table;
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string LatexText(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    if (c == '%' || c == '_' || c == '&' || c == '#' || c == '$') escaped += '\\';
    escaped += c;
  }
  return escaped;
}

}  // namespace

std::string Percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", 100.0 * fraction);
  return text;
}

std::string PercentInterval(double low, double high) { return "[" + Percent(low) + ", " + Percent(high) + "]"; }

std::string Points(double difference) {
  char text[32];
  std::snprintf(text, sizeof(text), "%+.1f", 100.0 * difference);
  return text;
}

std::string Seconds(const Json& value) {
  if (value.is_null()) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f", value.get<double>());
  return text;
}

std::string PValue(double p) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", p);
  return text;
}

std::vector<TextTable> SweepTables(const Json& summary) {
  std::vector<TextTable> tables;
  const bool several_labels = summary["labels"].size() > 1;
  for (const Json& suite : summary["success"]) tables.push_back(SuccessTable(suite, several_labels));
  tables.push_back(IdMinusOodTable(summary));
  tables.push_back(PairedTable(summary));
  tables.push_back(LengthTable(summary));
  tables.push_back(GaltTable(summary));
  for (TextTable& table : StageFunnelTables(summary["stages"])) tables.push_back(std::move(table));
  if (summary.contains("failure_events")) {
    for (TextTable& table : FailureEventTables(summary["failure_events"])) tables.push_back(std::move(table));
  }
  if (summary.contains("gaze")) {
    for (TextTable& table : GazeTables(summary["gaze"])) tables.push_back(std::move(table));
  }
  if (!summary["paired_camera_sets"].empty()) tables.push_back(CameraSetPairTable(summary));
  if (summary.contains("paired_perturbations")) tables.push_back(PerturbationPairTable(summary));
  if (summary.contains("sequential")) tables.push_back(SequentialTable(summary));
  if (!summary["seed_groups"].empty()) tables.push_back(SeedGroupTable(summary));
  tables.push_back(HeadlineTable(summary));
  return tables;
}

std::string ToMarkdown(const TextTable& table) {
  std::ostringstream out;
  out << "**" << table.title << "**\n\n|";
  for (const std::string& name : table.header) out << " " << name << " |";
  out << "\n|:---|";
  for (std::size_t c = 1; c < table.header.size(); ++c) out << "---:|";
  out << "\n";
  for (const std::vector<std::string>& row : table.rows) {
    out << "|";
    for (const std::string& cell : row) out << " " << cell << " |";
    out << "\n";
  }
  if (table.rows.empty()) out << "\n(no rows: the sweep has no cells for this table)\n";
  if (!table.note.empty()) out << "\n" << table.note << "\n";
  return out.str();
}

std::string ToCsv(const TextTable& table) {
  std::ostringstream out;
  for (std::size_t c = 0; c < table.header.size(); ++c) out << (c ? "," : "") << CsvField(table.header[c]);
  out << "\n";
  for (const std::vector<std::string>& row : table.rows) {
    for (std::size_t c = 0; c < row.size(); ++c) out << (c ? "," : "") << CsvField(row[c]);
    out << "\n";
  }
  return out.str();
}

std::string ToLatex(const TextTable& table) {
  std::ostringstream out;
  out << "% needs \\usepackage{booktabs}\n\\begin{table}\n\\centering\n\\caption{" << LatexText(table.title) << "}\n"
      << "\\begin{tabular}{l" << std::string(table.header.size() - 1, 'r') << "}\n\\toprule\n";
  const auto line = [&out](const std::vector<std::string>& cells) {
    for (std::size_t c = 0; c < cells.size(); ++c) out << (c ? " & " : "") << LatexText(cells[c]);
    out << " \\\\\n";
  };
  line(table.header);
  out << "\\midrule\n";
  for (const std::vector<std::string>& row : table.rows) line(row);
  out << "\\bottomrule\n\\end{tabular}\n";
  if (!table.note.empty()) out << "\\par\\smallskip{\\footnotesize " << LatexText(table.note) << "}\n";
  out << "\\end{table}\n";
  return out.str();
}

}  // namespace tavis::batch::report

#include "batch/report/paper_table.h"

#include <algorithm>
#include <sstream>
#include <vector>

#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

struct Column {
  std::string robot, split, camera;
};

std::string RobotTitle(const std::string& robot) {
  if (robot == "gr1t2") return "GR1T2";
  if (robot == "reachy2") return "Reachy2";
  return robot;
}

std::string SplitTitle(const std::string& split) {
  if (split == "id") return "ID";
  if (split == "ood-spatial") return "OOD-spatial";
  if (split == "ood-init-pose") return "OOD-init-pose";
  return split;
}

std::string Escaped(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    if (c == '%' || c == '_' || c == '&' || c == '#' || c == '$') escaped += '\\';
    escaped += c;
  }
  return escaped;
}

// The rate of one suite entry's column, or "--".
std::string Rate(const Json& suite, const Column& column, const std::string& task) {
  for (const Json& entry : suite["columns"]) {
    if (entry["robot"] != column.robot || entry["split"] != column.split || entry["camera"] != column.camera) continue;
    if (task.empty()) return Percent(entry["task_average"]);
    for (const Json& row : entry["tasks"]) {
      if (row["task"] == task && row.contains("success_rate")) return Percent(row["success_rate"]);
    }
  }
  return "--";
}

}  // namespace

std::string PaperTable1Latex(const Json& summary, const std::string& label) {
  std::vector<const Json*> suites;
  for (const Json& suite : summary["success"]) {
    if (suite["label"] == label) suites.push_back(&suite);
  }
  std::vector<Column> columns;
  for (const char* robot : {"gr1t2", "reachy2"}) {
    for (const char* split : {"id", "ood-spatial", "ood-init-pose"}) {
      for (const char* camera : {"head", "fixed"}) {
        for (const Json* suite : suites) {
          const bool present = std::any_of((*suite)["columns"].begin(), (*suite)["columns"].end(), [&](const Json& c) {
            return c["robot"] == robot && c["split"] == split && c["camera"] == camera;
          });
          if (present) {
            columns.push_back({robot, split, camera});
            break;
          }
        }
      }
    }
  }
  std::ostringstream out;
  out << "% Table 1 layout; needs \\usepackage{booktabs}\n\\begin{table*}\n\\centering\n\\caption{Success rate (\\%) "
         "of "
      << Escaped(label)
      << " per task, robot, split and camera (96 episodes per cell in the paper); suite mean: the task average.}\n"
      << "\\begin{tabular}{l" << std::string(columns.size(), 'c') << "}\n\\toprule\n";
  // Header rows: robots, splits, cameras, each spanning its columns.
  const auto spans = [&](auto key, auto title) {
    std::string line;
    std::size_t i = 0;
    std::vector<std::string> rules;
    while (i < columns.size()) {
      std::size_t j = i;
      while (j < columns.size() && key(columns[j]) == key(columns[i])) ++j;
      line += " & \\multicolumn{" + std::to_string(j - i) + "}{c}{" + title(columns[i]) + "}";
      rules.push_back("\\cmidrule(lr){" + std::to_string(i + 2) + "-" + std::to_string(j + 1) + "}");
      i = j;
    }
    out << line << " \\\\\n";
    for (const std::string& rule : rules) out << rule;
    out << "\n";
  };
  spans([](const Column& c) { return c.robot; }, [](const Column& c) { return RobotTitle(c.robot); });
  spans([](const Column& c) { return c.robot + c.split; }, [](const Column& c) { return SplitTitle(c.split); });
  out << "Task";
  for (const Column& column : columns)
    out << " & " << (column.camera == "head" ? "Head" : column.camera == "fixed" ? "Fixed" : Escaped(column.camera));
  out << " \\\\\n\\midrule\n";
  for (const Json* suite : suites) {
    for (const Json& row : (*suite)["columns"][0]["tasks"]) {
      const std::string task = row["task"];
      out << Escaped(task);
      for (const Column& column : columns) out << " & " << Rate(*suite, column, task);
      out << " \\\\\n";
    }
    out << "\\midrule\n\\textit{" << Escaped((*suite)["title"].get<std::string>()) << " mean}";
    for (const Column& column : columns) out << " & " << Rate(*suite, column, "");
    out << " \\\\\n" << (suite == suites.back() ? "\\bottomrule\n" : "\\midrule\n");
  }
  out << "\\end{tabular}\n\\end{table*}\n";
  return out.str();
}

}  // namespace tavis::batch::report

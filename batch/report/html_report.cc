#include "batch/report/html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <vector>

#include "batch/report/figure_drawing.h"
#include "batch/report/gaze_figures.h"
#include "batch/report/paper_figures.h"
#include "batch/report/sequential_section.h"
#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

std::string Escape(const std::string& text) { return EscapeXml(text); }

const char* SplitColour(const std::string& split) {
  if (split == "id") return "#1f77b4";
  if (split == "ood-spatial") return "#ff7f0e";
  return "#2ca02c";
}

// Success rate and Wilson interval of every pooled cell of one suite and robot: a row per task,
// split and camera; a filled dot for head, a hollow one for fixed.
std::string SuccessPlot(const Json& suite, const std::string& robot) {
  const std::string policy = suite["label"];
  struct Row {
    std::string label, split, camera;
    Json rate;
  };
  std::vector<Row> rows;
  const Json& columns = suite["columns"];
  for (std::size_t t = 0; t < columns[0]["tasks"].size(); ++t) {
    for (const Json& column : columns) {
      if (column["robot"] != robot || !column["tasks"][t].contains("success_rate")) continue;
      rows.push_back({column["tasks"][t]["task"].get<std::string>() + " " + column["split"].get<std::string>() + " " +
                          column["camera"].get<std::string>(),
                      column["split"], column["camera"], column["tasks"][t]});
    }
  }
  if (rows.empty()) return "";
  const int left = 330, width = 300, row_height = 16, top = 24;
  const int height = top + row_height * static_cast<int>(rows.size()) + 10;
  std::ostringstream svg;
  svg << "<figure><figcaption>" << Escape(policy + ": " + suite["title"].get<std::string>() + ", " + robot)
      << ": success rate with 95% Wilson interval (filled: head, hollow: fixed)</figcaption>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << left + width + 20 << "\" height=\"" << height
      << "\">\n";
  for (int percent = 0; percent <= 100; percent += 25) {
    const double x = left + width * percent / 100.0;
    svg << "<line x1=\"" << x << "\" y1=\"" << top - 6 << "\" x2=\"" << x << "\" y2=\"" << height - 8
        << "\" stroke=\"#ddd\"/><text x=\"" << x << "\" y=\"" << top - 10
        << "\" font-size=\"10\" text-anchor=\"middle\">" << percent << "%</text>\n";
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    const double y = top + row_height * (static_cast<double>(i) + 0.5);
    const double low = left + width * row.rate["ci_low"].get<double>();
    const double high = left + width * row.rate["ci_high"].get<double>();
    const double x = left + width * row.rate["success_rate"].get<double>();
    const char* colour = SplitColour(row.split);
    svg << "<text x=\"" << left - 6 << "\" y=\"" << y + 3 << "\" font-size=\"10\" text-anchor=\"end\">"
        << Escape(row.label) << "</text><line x1=\"" << low << "\" y1=\"" << y << "\" x2=\"" << high << "\" y2=\"" << y
        << "\" stroke=\"" << colour << "\" stroke-width=\"2\"/><circle cx=\"" << x << "\" cy=\"" << y
        << "\" r=\"4\" class=\"success-point\" stroke=\"" << colour << "\" fill=\""
        << (row.camera == "head" ? colour : "white") << "\"><title>" << Escape(row.label) << ": "
        << Percent(row.rate["success_rate"]) << "% " << PercentInterval(row.rate["ci_low"], row.rate["ci_high"])
        << "</title></circle>\n";
  }
  svg << "</svg></figure>\n";
  return svg.str();
}

double HumanGalt(const std::string& robot) {
  if (robot == "gr1t2") return kHumanGaltGr1t2;
  if (robot == "reachy2") return kHumanGaltReachy2;
  return 0.0;
}

std::vector<std::string> Robots(const Json& summary) {
  std::vector<std::string> robots;
  for (const Json& cell : summary["cells"]) {
    const std::string robot = cell["robot"];
    if (std::find(robots.begin(), robots.end(), robot) == robots.end()) robots.push_back(robot);
  }
  return robots;
}

std::string HtmlTable(const TextTable& table) {
  std::ostringstream html;
  html << "<h3>" << Escape(table.title) << "</h3>\n<table id=\"" << Escape(table.name) << "\"><tr>";
  for (const std::string& name : table.header) html << "<th>" << Escape(name) << "</th>";
  html << "</tr>\n";
  for (const std::vector<std::string>& row : table.rows) {
    html << "<tr>";
    for (const std::string& cell : row) html << "<td>" << Escape(cell) << "</td>";
    html << "</tr>\n";
  }
  html << "</table>\n";
  if (!table.note.empty()) html << "<p class=\"note\">" << Escape(table.note) << "</p>\n";
  return html.str();
}

std::string FigureHtml(const Figure& figure) {
  return "<figure><figcaption>" + Escape(figure.caption) + "</figcaption>\n" + figure.canvas.Svg(figure.name) +
         "</figure>\n";
}

std::string Field(const std::string& cell, const std::string& field, const std::string& text) {
  return "<td data-cell=\"" + Escape(cell) + "\" data-field=\"" + field + "\">" + Escape(text) + "</td>";
}

// Every cell with its own numbers (percent with one decimal, seconds with two), for reading and
// for checking against summary.json: a heading for every column of its rows.
std::string CellTable(const Json& summary) {
  std::ostringstream html;
  html << "<h3>Cells</h3>\n<table "
          "id=\"cells\"><tr><th>cell</th><th>policy</th><th>episodes</th><th>successful</th><th>success %</th>"
          "<th>ci low %</th><th>ci high %</th><th>successful length mean s</th><th>GALT mean s</th></tr>\n";
  for (const Json& cell : summary["cells"]) {
    const std::string id = cell["id"];
    html << "<tr><td>" << Escape(id) << "</td>" << Field(id, "label", cell["label"].get<std::string>())
         << Field(id, "n_episodes", std::to_string(cell["n_episodes"].get<int64_t>()))
         << Field(id, "n_successful", std::to_string(cell["n_successful"].get<int64_t>()))
         << Field(id, "success_rate", Percent(cell["success_rate"])) << Field(id, "ci_low", Percent(cell["ci_low"]))
         << Field(id, "ci_high", Percent(cell["ci_high"]))
         << Field(id, "successful_length_mean_s", Seconds(cell["successful_length_s"]["mean"]))
         << Field(id, "galt_mean_s", cell["galt"].is_null() ? "-" : Seconds(cell["galt"]["mean_s"])) << "</tr>\n";
  }
  html << "</table>\n";
  return html.str();
}

// The policies, with what their servers reported.
std::string PolicyList(const Json& summary) {
  std::ostringstream html;
  html << "<ul id=\"policies\">\n";
  for (const Json& label : summary["labels"]) {
    html << "<li><b>" << Escape(label["label"].get<std::string>()) << "</b>: policy "
         << Escape(label["policy"].get<std::string>());
    if (!label["seed_group"].get<std::string>().empty())
      html << ", seed group " << Escape(label["seed_group"].get<std::string>());
    for (const Json& cell : summary["cells"]) {
      if (cell["label"] == label["label"] && !cell["server_metadata"].empty()) {
        html << ", server metadata <code>" << Escape(cell["server_metadata"].dump()) << "</code>";
        break;
      }
    }
    html << "</li>\n";
  }
  html << "</ul>\n";
  return html.str();
}

}  // namespace

std::string SweepHtmlReport(const Json& summary, const Json& manifest) {
  std::ostringstream html;
  html
      << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>TAVIS sweep report</title>\n<style>\n"
         "body{font-family:sans-serif;margin:2em;max-width:1100px;color:#222}table{border-collapse:collapse;margin:0."
         "5em 0}"
         "td,th{border:1px solid #ccc;padding:2px 6px;font-size:12px;text-align:right}td:first-child{text-align:left}"
         "figure{margin:1em 0}figcaption{font-weight:bold;font-size:13px}.note{font-size:12px;color:#555}"
         "pre{background:#f6f6f6;padding:0.5em;font-size:11px;overflow:auto}\n</style></head><body>\n"
      << "<h1>TAVIS sweep report</h1>\n<p>" << summary["cells"].size()
      << (summary["cells"].size() == 1 ? " cell" : " cells") << " of " << summary["labels"].size()
      << (summary["labels"].size() == 1 ? " policy, " : " policies, ") << summary["spec"]["episodes"]
      << " episodes per cell; program " << Escape(manifest.value("version", ""))
      << ". Cells of different policies are never pooled.</p>\n"
      << PolicyList(summary) << "<h2>Success rates</h2>\n";
  const std::vector<std::string> robots = Robots(summary);
  for (const Json& suite : summary["success"]) {
    for (const std::string& robot : robots) html << SuccessPlot(suite, robot);
  }
  html << "<h2>The paper's figures</h2>\n";
  for (const Figure& figure : DrawPaperFigures(summary["figures"])) html << FigureHtml(figure);
  html << "<h2>GALT distributions per policy and robot (id split, head camera, successful episodes, the detector's "
          "window "
          "[-0.5, 4.0] s)</h2>\n";
  for (const Json& label : summary["labels"]) {
    for (const std::string& robot : robots) {
      std::vector<double> values;
      for (const Json& cell : summary["cells"]) {
        if (cell["label"] != label["label"] || cell["robot"] != robot || cell["split"] != "id" ||
            cell["galt"].is_null())
          continue;
        for (const Json& value : cell["galt"]["values_s"]) values.push_back(value);
      }
      if (values.empty()) continue;
      char marker[64];
      std::snprintf(marker, sizeof(marker), "human %.2f s", HumanGalt(robot));
      const std::string name = label["label"].get<std::string>() + " " + robot;
      html << FigureHtml(DrawHistogram("galt_" + label["label"].get<std::string>() + "_" + robot, name + ": GALT (s)",
                                       {{name + " head", values}}, kGaltFigureLow, 4.0, 18, "GALT (s)",
                                       HumanGalt(robot) > 0
                                           ? std::make_optional(std::make_pair(HumanGalt(robot), std::string(marker)))
                                           : std::nullopt));
    }
  }
  html << "<h2>Successful-episode length distributions</h2>\n";
  for (const Json& label : summary["labels"]) {
    for (const std::string& robot : robots) {
      std::vector<std::pair<std::string, std::vector<double>>> series;
      double upper = 1.0;
      for (const char* camera : {"head", "fixed"}) {
        std::vector<double> values;
        for (const Json& cell : summary["cells"]) {
          if (cell["label"] != label["label"] || cell["robot"] != robot || cell["camera"] != camera) continue;
          for (const Json& value : cell["successful_length_s"]["values"]) values.push_back(value);
        }
        for (const double value : values) upper = std::max(upper, value * 1.05);
        if (!values.empty()) series.emplace_back(camera, values);
      }
      const std::string name = label["label"].get<std::string>() + " " + robot;
      if (!series.empty()) {
        html << FigureHtml(DrawHistogram("length_" + label["label"].get<std::string>() + "_" + robot,
                                         name + ": length of successful episodes (s)", series, 0.0, upper, 24,
                                         "length (s)", std::nullopt));
      }
    }
  }
  if (summary.contains("gaze_figures") && !summary["gaze_figures"].is_null()) {
    html << "<h2>Gaze: verified GALT, anchors and gaze on target (docs/gaze.md)</h2>\n";
    for (const Figure& figure : DrawGazeFigures(summary["gaze_figures"])) html << FigureHtml(figure);
  }
  html << SequentialHtml(summary);
  html << "<h2>Tables</h2>\n";
  for (const TextTable& table : SweepTables(summary)) html << HtmlTable(table);
  html << CellTable(summary);
  html << "<h2>Spec</h2>\n<pre id=\"spec\">" << Escape(summary["spec"].dump(2))
       << "</pre>\n<h2>Manifest</h2>\n<pre id=\"manifest\">" << Escape(manifest.dump(2)) << "</pre>\n</body></html>\n";
  return html.str();
}

}  // namespace tavis::batch::report

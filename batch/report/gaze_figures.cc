#include "batch/report/gaze_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "batch/cell/statistics.h"
#include "batch/report/paper_figures.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

// The labels a figures choice stands for: a seed group's checkpoints, or the label itself.
std::vector<std::string> LabelsOf(const Json& summary, const std::string& name) {
  for (const Json& group : summary["seed_groups"]) {
    if (group["seed_group"] == name) return group["labels"].get<std::vector<std::string>>();
  }
  return {name};
}

bool Contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// The gaze rows of `labels` on the id split with the head camera.
std::vector<const Json*> IdHeadRows(const Json& summary, const std::vector<std::string>& labels) {
  std::vector<const Json*> rows;
  for (const Json& row : summary["gaze"]) {
    if (Contains(labels, row["label"]) && row["split"] == "id" && row["camera"] == "head") rows.push_back(&row);
  }
  return rows;
}

Json HistogramJson(const std::vector<double>& values) {
  int outside = 0;
  for (const double value : values) outside += value >= kGazeGaltLow && value <= kGazeGaltHigh ? 0 : 1;
  return {{"n", values.size()},
          {"n_outside_window", outside},
          {"median", values.empty() ? Json() : Json(cell::Median(values))},
          {"counts", HistogramCounts(values, kGazeGaltLow, kGazeGaltHigh, kGazeGaltBins)}};
}

Json GaltVerified(const Json& summary, const std::string& name) {
  std::vector<std::string> tasks;
  std::vector<std::pair<std::vector<double>, std::vector<double>>> values;  // [task]: verified, unverified
  for (const Json* row : IdHeadRows(summary, LabelsOf(summary, name))) {
    auto task = std::find(tasks.begin(), tasks.end(), (*row)["task"]);
    if (task == tasks.end()) {
      tasks.push_back((*row)["task"]);
      values.emplace_back();
      task = tasks.end() - 1;
    }
    auto& [verified, unverified] = values[static_cast<std::size_t>(task - tasks.begin())];
    for (const Json& value : (*row)["galt_verified_values_s"]) verified.push_back(value);
    for (const Json& value : (*row)["galt_unverified_values_s"]) unverified.push_back(value);
  }
  Json rows = Json::array();
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    if (values[t].first.empty() && values[t].second.empty()) continue;
    rows.push_back({{"task", tasks[t]},
                    {"verified", HistogramJson(values[t].first)},
                    {"unverified", HistogramJson(values[t].second)}});
  }
  if (rows.empty()) return nullptr;
  return {{"policy", name},
          {"split", "id"},
          {"camera", "head"},
          {"bins", {{"low", kGazeGaltLow}, {"high", kGazeGaltHigh}, {"count", kGazeGaltBins}}},
          {"tasks", rows}};
}

Json Anchors(const Json& summary, const std::string& name) {
  Json rows = Json::array();
  for (const Json* row : IdHeadRows(summary, LabelsOf(summary, name))) {
    for (const Json& anchor : (*row)["gaze"]["anchors"]) {
      if (anchor["n"].get<int64_t>() == 0) continue;
      rows.push_back({{"label", (*row)["label"]},
                      {"task", (*row)["task"]},
                      {"robot", (*row)["robot"]},
                      {"anchor", anchor["anchor"]},
                      {"event", anchor["event"]},
                      {"n", anchor["n"]},
                      {"median_s", anchor["median_s"]},
                      {"q1_s", anchor["q1_s"]},
                      {"q3_s", anchor["q3_s"]}});
    }
  }
  if (rows.empty()) return nullptr;
  return {{"policy", name}, {"split", "id"}, {"camera", "head"}, {"rows", rows}};
}

Json GazeOnTarget(const Json& summary) {
  Json series = Json::array(), groups = Json::array();
  for (const Json& row : summary["gaze"]) {
    const Json& ratio = row["gaze"]["gaze_on_target_ratio_mean"];
    if (row["split"] != "id" || ratio.is_null()) continue;
    const std::string name = row["label"].get<std::string>() + " " + row["camera"].get<std::string>();
    if (std::find(series.begin(), series.end(), name) == series.end()) series.push_back(name);
    auto group = std::find_if(groups.begin(), groups.end(),
                              [&](const Json& g) { return g["task"] == row["task"] && g["robot"] == row["robot"]; });
    if (group == groups.end()) {
      groups.push_back({{"task", row["task"]}, {"robot", row["robot"]}, {"bars", Json::array()}});
      group = groups.end() - 1;
    }
    (*group)["bars"].push_back(
        {{"series", name}, {"label", row["label"]}, {"camera", row["camera"]}, {"value", ratio}});
  }
  if (groups.empty()) return nullptr;
  return {{"split", "id"}, {"series", series}, {"groups", groups}};
}

std::string SecondsText(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f s", value);
  return text;
}

double XOf(double value, double left, double width, double low, double high) {
  return left + width * (value - low) / (high - low);
}

Figure DrawGaltVerified(const Json& figure) {
  constexpr double kTitleSize = 13, kPanelTitleSize = 11, kLegendSize = 10;
  const double low = figure["bins"]["low"], high = figure["bins"]["high"];
  const Json& tasks = figure["tasks"];
  const double panel_width = 480, panel_height = 110, left = 40, top = 40, pitch = panel_height + 70;
  const std::string title = "GALT verified by the gaze vs not, per task (" + figure["policy"].get<std::string>() +
                            ", id, head camera, successful episodes)";
  std::vector<std::vector<std::pair<std::string, std::size_t>>> legends;
  double legend_width = 0;
  for (const Json& row : tasks) {
    std::vector<std::pair<std::string, std::size_t>> lines;
    std::size_t s = 0;
    for (const char* which : {"verified", "unverified"}) {
      const Json& part = row[which];
      std::string text = std::string(which) + " (n = " + std::to_string(part["n"].get<int>());
      if (part["n_outside_window"].get<int>() > 0)
        text += ", " + std::to_string(part["n_outside_window"].get<int>()) + " outside";
      lines.push_back({text + ")", s});
      if (!part["median"].is_null()) lines.push_back({"median " + SecondsText(part["median"].get<double>()), s});
      ++s;
    }
    for (const auto& line : lines) legend_width = std::max(legend_width, Canvas::TextWidth(line.first, kLegendSize));
    legends.push_back(lines);
  }
  const double legend_left = left + panel_width + 14;
  const double width = std::max(legend_left + legend_width + 10, left + Canvas::TextWidth(title, kTitleSize) + 10);
  Canvas canvas(static_cast<int>(std::ceil(width)), static_cast<int>(top + pitch * static_cast<double>(tasks.size())));
  canvas.Text(left, 18, title, kTitleSize);
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    const Json& row = tasks[t];
    const double y0 = top + pitch * static_cast<double>(t) + 20;
    canvas.Text(left, y0 - 8, row["task"].get<std::string>(), kPanelTitleSize);
    HistogramPanel(canvas, left, y0, panel_width, panel_height, low, high,
                   {{"verified", row["verified"]["counts"].get<std::vector<int>>()},
                    {"unverified", row["unverified"]["counts"].get<std::vector<int>>()}},
                   "GALT (s), " + Num(figure["bins"]["count"].get<int>()) + " bins");
    std::size_t s = 0;
    for (const char* which : {"verified", "unverified"}) {
      const Json& median = row[which]["median"];
      if (!median.is_null() && median.get<double>() >= low && median.get<double>() <= high) {
        const double x = XOf(median, left, panel_width, low, high);
        canvas.Line(x, y0, x, y0 + panel_height, Colour(s), 2.0, true,
                    {{"series", which}, {"task", row["task"]}, {"median", Num(median)}});
      }
      ++s;
    }
    for (std::size_t line = 0; line < legends[t].size(); ++line) {
      canvas.Text(legend_left, y0 + 12 + 14 * static_cast<double>(line), legends[t][line].first, kLegendSize,
                  Canvas::Anchor::kStart, Colour(legends[t][line].second));
    }
  }
  return {"gaze_galt_verified",
          "Gaze: GALT of the episodes whose head was on the target at the grasp (verified, blue) and of the others "
          "(orange), per task, medians dashed",
          std::move(canvas)};
}

Figure DrawAnchors(const Json& figure) {
  constexpr double kTitleSize = 13, kLabelSize = 10;
  const Json& rows = figure["rows"];
  std::vector<std::string> names;
  double label_width = 0, high = 0.5, low = 0.0;
  for (const Json& row : rows) {
    std::string name =
        row["task"].get<std::string>() + " " + row["robot"].get<std::string>() + " " + row["anchor"].get<std::string>();
    // A seed group's rows are its checkpoints': each names its label.
    if (row["label"] != figure["policy"]) name = row["label"].get<std::string>() + " " + name;
    names.push_back(name);
    label_width = std::max(label_width, Canvas::TextWidth(name, kLabelSize));
    high = std::max(high, row["q3_s"].get<double>());
    low = std::min(low, row["q1_s"].get<double>());
  }
  const std::vector<double> ticks = RoundTicks(low, high * 1.05);
  const double axis_low = std::min(low, ticks.front()), axis_high = std::max(high * 1.05, ticks.back());
  const double left = label_width + 20, top = 40, row_height = 16, width = 420;
  const std::string title = "Gaze anchors: lead time, median and interquartile range (" +
                            figure["policy"].get<std::string>() + ", id, head camera, successful episodes)";
  const double height = top + row_height * static_cast<double>(rows.size()) + 40;
  Canvas canvas(static_cast<int>(std::ceil(std::max(left + width + 20, 20 + Canvas::TextWidth(title, kTitleSize)))),
                static_cast<int>(height));
  canvas.Text(10, 18, title, kTitleSize);
  const double bottom = top + row_height * static_cast<double>(rows.size());
  for (const double tick : RoundTicks(axis_low, axis_high)) {
    const double x = XOf(tick, left, width, axis_low, axis_high);
    canvas.Line(x, top - 4, x, bottom, tick == 0.0 ? "#333333" : "#dddddd");
    canvas.Text(x, bottom + 13, Num(std::round(tick * 1000) / 1000), 9, Canvas::Anchor::kMiddle);
  }
  canvas.Text(left + width / 2, bottom + 27, "lead time (s): the fixation's start to the event", 9,
              Canvas::Anchor::kMiddle);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const Json& row = rows[r];
    const double y = top + row_height * static_cast<double>(r);
    const double q1 = row["q1_s"], q3 = row["q3_s"], median = row["median_s"];
    const std::string colour = Colour(r % 3);
    canvas.Text(left - 6, y + row_height - 4, names[r], kLabelSize, Canvas::Anchor::kEnd);
    const double x1 = XOf(q1, left, width, axis_low, axis_high), x3 = XOf(q3, left, width, axis_low, axis_high);
    canvas.Rect(x1, y + 3, std::max(1.0, x3 - x1), row_height - 6, colour, 0.35, colour,
                {{"label", row["label"]},
                 {"task", row["task"]},
                 {"robot", row["robot"]},
                 {"anchor", row["anchor"]},
                 {"n", std::to_string(row["n"].get<int64_t>())},
                 {"median", Num(median)},
                 {"q1", Num(q1)},
                 {"q3", Num(q3)}});
    const double xm = XOf(median, left, width, axis_low, axis_high);
    canvas.Line(xm, y + 1, xm, y + row_height - 1, "#222222", 2.0);
  }
  return {"gaze_anchors",
          "Gaze anchors: per task, robot and anchor, the lead time's median (black) and quartiles (box)",
          std::move(canvas)};
}

Figure DrawGazeOnTarget(const Json& figure) {
  std::vector<BarGroup> groups;
  const std::vector<std::string> series = figure["series"].get<std::vector<std::string>>();
  for (const Json& group : figure["groups"]) {
    BarGroup drawn{{group["task"].get<std::string>(), group["robot"].get<std::string>()}, {}};
    for (const std::string& name : series) {
      Json value;
      DataAttributes data = {{"task", group["task"]}, {"robot", group["robot"]}};
      for (const Json& bar : group["bars"]) {
        if (bar["series"] != name) continue;
        value = {{"mean", bar["value"]}, {"std", 0.0}, {"checkpoints", 1}};
        data.push_back({"label", bar["label"]});
        data.push_back({"camera", bar["camera"]});
      }
      drawn.bars.push_back({name, value, data});
    }
    groups.push_back(drawn);
  }
  return {"gaze_on_target",
          "Gaze on target: the mean share of the 3 s before the grasp the head looked at the target, per task and "
          "robot (id split), a bar per policy and camera",
          GroupedBars("Gaze on target before the grasp (id split), per policy and camera", groups, series)};
}

}  // namespace

Json GazeFiguresJson(const Json& summary, const Json& choices) {
  if (!summary.contains("gaze") || summary["labels"].empty()) return nullptr;
  const std::string main = choices.contains("policy") ? choices["policy"].get<std::string>()
                                                      : summary["labels"][0]["label"].get<std::string>();
  const std::string name = choices.contains("gaze") ? choices["gaze"].get<std::string>() : main;
  return {{"galt_verified", GaltVerified(summary, name)},
          {"anchors", Anchors(summary, name)},
          {"gaze_on_target", GazeOnTarget(summary)}};
}

std::vector<Figure> DrawGazeFigures(const Json& figures) {
  std::vector<Figure> drawn;
  if (figures.is_null()) return drawn;
  if (!figures["galt_verified"].is_null()) drawn.push_back(DrawGaltVerified(figures["galt_verified"]));
  if (!figures["anchors"].is_null()) drawn.push_back(DrawAnchors(figures["anchors"]));
  if (!figures["gaze_on_target"].is_null()) drawn.push_back(DrawGazeOnTarget(figures["gaze_on_target"]));
  return drawn;
}

}  // namespace tavis::batch::report

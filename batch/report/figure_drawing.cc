#include "batch/report/figure_drawing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "batch/report/paper_figures.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

const char* const kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"};

std::string PercentText(double fraction) {
  char text[16];
  std::snprintf(text, sizeof(text), "%.1f", 100.0 * fraction);
  return text;
}

// A rate axis (0 to 100 %) at the left of a plot area, with grid lines.
void RateAxis(Canvas& canvas, double left, double top, double width, double height) {
  for (int percent = 0; percent <= 100; percent += 25) {
    const double y = top + height * (1.0 - percent / 100.0);
    canvas.Line(left, y, left + width, y, percent == 0 ? "#333333" : "#dddddd");
    canvas.Text(left - 4, y + 4, std::to_string(percent) + "%", 10, Canvas::Anchor::kEnd);
  }
}

struct Bar {
  std::string series;  // legend name
  Json value;          // {mean, std, checkpoints} or null (not evaluated)
  DataAttributes data;
};

struct BarGroup {
  std::string label;
  std::vector<Bar> bars;
};

// Grouped bars of rates with their spread across checkpoints (when there are several) as
// whiskers; a legend of the series names in order.
Canvas GroupedBars(const std::string& title, const std::vector<BarGroup>& groups, const std::vector<std::string>& series) {
  const double left = 50, top = 40, height = 220, bar_width = 18, gap = 22;
  double width = gap;
  for (const BarGroup& group : groups) width += bar_width * static_cast<double>(group.bars.size()) + gap;
  width = std::max(width, 200.0);
  Canvas canvas(std::max(640, static_cast<int>(left + width + 170)), static_cast<int>(top + height + 60));
  canvas.Text(left, 18, title, 13);
  RateAxis(canvas, left, top, width, height);
  double x = left + gap;
  for (const BarGroup& group : groups) {
    const double group_width = bar_width * static_cast<double>(group.bars.size());
    for (std::size_t b = 0; b < group.bars.size(); ++b) {
      const Bar& bar = group.bars[b];
      const std::size_t s = static_cast<std::size_t>(std::find(series.begin(), series.end(), bar.series) - series.begin());
      const std::string colour = kColours[s % 6];
      const double bx = x + bar_width * static_cast<double>(b);
      if (bar.value.is_null()) {
        canvas.Text(bx + bar_width / 2, top + height - 3, "-", 10, Canvas::Anchor::kMiddle);
        continue;
      }
      const double mean = bar.value["mean"], spread = bar.value["std"];
      DataAttributes data = bar.data;
      data.push_back({"series", bar.series});
      data.push_back({"value", Num(mean)});
      data.push_back({"std", Num(spread)});
      canvas.Rect(bx + 1, top + height * (1.0 - mean), bar_width - 2, height * mean, colour, 0.85, colour, data);
      if (bar.value["checkpoints"].get<int>() > 1) {
        const double low = std::max(0.0, mean - spread), high = std::min(1.0, mean + spread);
        const double cx = bx + bar_width / 2;
        canvas.Line(cx, top + height * (1.0 - low), cx, top + height * (1.0 - high), "#222222", 1.5);
      }
      canvas.Text(bx + bar_width / 2, top + height * (1.0 - mean) - 3, PercentText(mean), 8, Canvas::Anchor::kMiddle);
    }
    canvas.Text(x + group_width / 2, top + height + 16, group.label, 10, Canvas::Anchor::kMiddle);
    x += group_width + gap;
  }
  for (std::size_t s = 0; s < series.size(); ++s) {
    const double y = top + 14 * static_cast<double>(s);
    canvas.Rect(left + width + 12, y, 10, 10, kColours[s % 6], 0.85, "");
    canvas.Text(left + width + 26, y + 9, series[s], 11);
  }
  return canvas;
}

std::string GroupName(const Json& bar) { return bar["robot"].get<std::string>() + " " + bar["suite"].get<std::string>(); }

Figure HeadVsFixed(const Json& figure) {
  std::vector<std::string> robots;
  for (const Json& point : figure["points"]) {
    if (std::find(robots.begin(), robots.end(), point["robot"]) == robots.end()) robots.push_back(point["robot"]);
  }
  const double panel = 260, left = 50, top = 40, height = 240;
  // Wide enough for the title in the PNG's Hershey font too.
  Canvas canvas(std::max(640, static_cast<int>(left + panel * static_cast<double>(robots.size()) + 20)), static_cast<int>(top + height + 50));
  canvas.Text(left, 18, "Fig. 3a: head vs fixed camera, id split, per task (" + figure["policy"].get<std::string>() + ")", 13);
  for (std::size_t r = 0; r < robots.size(); ++r) {
    const double x0 = left + panel * static_cast<double>(r);
    RateAxis(canvas, x0, top, panel - 40, height);
    const double x_head = x0 + 40, x_fixed = x0 + panel - 80;
    canvas.Text(x_head, top + height + 16, "head", 11, Canvas::Anchor::kMiddle);
    canvas.Text(x_fixed, top + height + 16, "fixed", 11, Canvas::Anchor::kMiddle);
    canvas.Text(x0 + (panel - 40) / 2, top + height + 32, robots[r], 12, Canvas::Anchor::kMiddle);
    int t = 0;
    for (const Json& point : figure["points"]) {
      if (point["robot"] != robots[r]) continue;
      const std::string colour = kColours[t++ % 6];
      const double head = point["head"]["mean"], fixed = point["fixed"]["mean"];
      const double y_head = top + height * (1.0 - head), y_fixed = top + height * (1.0 - fixed);
      canvas.Line(x_head, y_head, x_fixed, y_fixed, colour, 1.5);
      const DataAttributes where = {{"task", point["task"]}, {"robot", point["robot"]}};
      DataAttributes head_data = where, fixed_data = where;
      head_data.push_back({"camera", "head"});
      head_data.push_back({"value", Num(head)});
      fixed_data.push_back({"camera", "fixed"});
      fixed_data.push_back({"value", Num(fixed)});
      canvas.Circle(x_head, y_head, 4, colour, true, head_data);
      canvas.Circle(x_fixed, y_fixed, 4, colour, false, fixed_data);
      canvas.Text(x_fixed + 8, y_fixed + 4, point["task"].get<std::string>(), 8, Canvas::Anchor::kStart, colour);
    }
  }
  return {"fig3a_head_vs_fixed", "Figure 3a: success rate with the head camera and with the fixed camera, id split; a line per task pairs them",
          std::move(canvas)};
}

Figure SingleVsMulti(const Json& figure) {
  const std::string single = figure["single"], multi = figure["multi"];
  std::vector<BarGroup> groups;
  for (const Json& bar : figure["bars"]) {
    const DataAttributes where = {{"suite", bar["suite"]}, {"robot", bar["robot"]}};
    groups.push_back({GroupName(bar), {{single, bar["single"], where}, {multi, bar["multi"], where}}});
  }
  return {"fig3b_single_vs_multi", "Figure 3b: suite means (id, head camera), " + single + " vs " + multi,
          GroupedBars("Fig. 3b: suite mean, id, head: " + single + " vs " + multi, groups, {single, multi})};
}

Figure Splits(const Json& figure) {
  std::vector<BarGroup> groups;
  const std::vector<std::string> splits = {"id", "ood-spatial", "ood-init-pose"};
  for (const Json& bar : figure["bars"]) {
    BarGroup group{GroupName(bar), {}};
    for (const std::string& split : splits) group.bars.push_back({split, bar[split], {{"suite", bar["suite"]}, {"robot", bar["robot"]}}});
    groups.push_back(group);
  }
  return {"fig3c_splits", "Figure 3c: suite means (head camera) of " + figure["policy"].get<std::string>() + " per split",
          GroupedBars("Fig. 3c: suite mean, head: id / ood-spatial / ood-init-pose (" + figure["policy"].get<std::string>() + ")", groups,
                      splits)};
}

Figure Ablation(const Json& figure) {
  std::vector<BarGroup> groups;
  std::vector<std::string> series;
  BarGroup mean{"mean over robots", {}};
  for (const Json& arm : figure["arms"]) {
    const std::string name = arm["arm"].get<std::string>() + " (" + arm["label"].get<std::string>() + ", " + arm["task"].get<std::string>() +
                             ", " + arm["camera"].get<std::string>() + ")";
    series.push_back(name);
    const Json value = arm["mean_over_robots"].is_null() ? Json() : Json({{"mean", arm["mean_over_robots"]}, {"std", 0.0}, {"checkpoints", 1}});
    mean.bars.push_back({name, value, {{"arm", arm["arm"]}, {"robot", "mean"}}});
  }
  groups.push_back(mean);
  for (const Json& first : figure["arms"][0]["per_robot"]) {
    BarGroup group{first["robot"], {}};
    for (std::size_t a = 0; a < figure["arms"].size(); ++a) {
      Json value;
      for (const Json& entry : figure["arms"][a]["per_robot"]) {
        if (entry["robot"] == first["robot"]) value = entry["rate"];
      }
      group.bars.push_back({series[a], value, {{"arm", figure["arms"][a]["arm"]}, {"robot", first["robot"]}}});
    }
    groups.push_back(group);
  }
  return {"fig3d_ablation", "Figure 3d: the active-vision ablation, id split: no AV (fixed camera), full AV (head + wrists), wrist only (head blocked)",
          GroupedBars("Fig. 3d: no-AV / full-AV / wrist-only", groups, series)};
}

// One step outline per series over the bins, each bin a data-carrying rectangle.
void HistogramPanel(Canvas& canvas, double left, double top, double width, double height, double low, double high,
                    const std::vector<std::pair<std::string, std::vector<int>>>& series, const std::string& unit) {
  const int bins = series.empty() ? 1 : static_cast<int>(series[0].second.size());
  int most = 1;
  for (const auto& [name, counts] : series) most = std::max(most, *std::max_element(counts.begin(), counts.end()));
  const double bottom = top + height;
  canvas.Line(left, bottom, left + width, bottom, "#333333");
  for (int tick = 0; tick <= 4; ++tick) {
    const double value = low + (high - low) * tick / 4.0;
    canvas.Text(left + width * tick / 4.0, bottom + 13, Num(std::round(value * 100) / 100) + " " + unit, 9, Canvas::Anchor::kMiddle);
  }
  canvas.Text(left - 3, top + 8, std::to_string(most), 9, Canvas::Anchor::kEnd);
  for (std::size_t s = 0; s < series.size(); ++s) {
    const std::string colour = kColours[s % 6];
    const std::vector<int>& counts = series[s].second;
    double previous = bottom;
    for (int b = 0; b < bins; ++b) {
      const double x0 = left + width * b / bins, x1 = left + width * (b + 1) / bins;
      const double y = bottom - height * counts[static_cast<std::size_t>(b)] / most;
      canvas.Rect(x0, y, x1 - x0, bottom - y, colour, 0.2, "",
                  {{"series", series[s].first}, {"bin", std::to_string(b)}, {"low", Num(low + (high - low) * b / bins)},
                   {"high", Num(low + (high - low) * (b + 1) / bins)}, {"count", std::to_string(counts[static_cast<std::size_t>(b)])}});
      canvas.Line(x0, previous, x0, y, colour);
      canvas.Line(x0, y, x1, y, colour);
      previous = y;
    }
    canvas.Line(left + width, previous, left + width, bottom, colour);
  }
}

double XOf(double value, double left, double width, double low, double high) { return left + width * (value - low) / (high - low); }

Figure GaltFigure(const Json& figure) {
  const double low = figure["bins"]["low"], high = figure["bins"]["high"];
  const Json& tasks = figure["tasks"];
  const double panel_width = 300, panel_height = 130, left = 40, top = 50, pitch = panel_height + 70;
  Canvas canvas(static_cast<int>(left + panel_width + 420), static_cast<int>(top + pitch * static_cast<double>(tasks.size())));
  const std::string reference = figure["reference"].is_null() ? "no reference" : figure["reference"].get<std::string>();
  char window[32];
  std::snprintf(window, sizeof(window), "%.1f", figure["window_s"].get<double>());
  canvas.Text(left, 18, "Fig. 4: GALT per TAVIS-Head task (id, head camera, successful episodes), window [-0.5, " + std::string(window) + "] s", 13);
  canvas.Text(left, 34, figure["policy"].get<std::string>() + " (blue) vs " + reference + " (orange); dashed: medians", 11);
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    const Json& row = tasks[t];
    const double y0 = top + pitch * static_cast<double>(t) + 20;
    std::vector<std::pair<std::string, std::vector<int>>> series = {{"policy", row["policy"]["counts"].get<std::vector<int>>()}};
    if (!row["reference"].is_null()) series.push_back({"reference", row["reference"]["counts"].get<std::vector<int>>()});
    std::string title = row["task"].get<std::string>() + ": n = " + std::to_string(row["policy"]["n"].get<int>());
    if (!row["reference"].is_null()) title += " vs " + std::to_string(row["reference"]["n"].get<int>());
    if (!row["relative_median_difference"].is_null()) {
      char text[64];
      std::snprintf(text, sizeof(text), ", |delta median| / median = %.1f%%", 100.0 * row["relative_median_difference"].get<double>());
      title += text;
    }
    canvas.Text(left, y0 - 6, title, 11);
    HistogramPanel(canvas, left, y0, panel_width, panel_height, low, high, series, "s");
    int s = 0;
    for (const char* which : {"policy", "reference"}) {
      const Json& part = row[which];
      if (part.is_null() || part["median"].is_null()) {
        ++s;
        continue;
      }
      const double median = part["median"];
      const double x = XOf(median, left, panel_width, low, high);
      canvas.Line(x, y0, x, y0 + panel_height, kColours[s], 2.0, true, {{"series", which}, {"task", row["task"]}, {"median", Num(median)}});
      canvas.Text(left + panel_width + 10, y0 + 14 + 14 * s, std::string(which) + " median " + Num(std::round(median * 100) / 100) + " s", 10,
                  Canvas::Anchor::kStart, kColours[s]);
      ++s;
    }
  }
  return {"fig4_galt", "Figure 4: GALT per TAVIS-Head task, policy vs reference, 20 bins, medians dashed", std::move(canvas)};
}

}  // namespace

std::vector<Figure> DrawPaperFigures(const Json& figures) {
  std::vector<Figure> drawn;
  if (figures.is_null()) return drawn;
  if (!figures["fig3a"].is_null()) drawn.push_back(HeadVsFixed(figures["fig3a"]));
  if (!figures["fig3b"].is_null()) drawn.push_back(SingleVsMulti(figures["fig3b"]));
  if (!figures["fig3c"].is_null()) drawn.push_back(Splits(figures["fig3c"]));
  if (!figures["fig3d"].is_null()) drawn.push_back(Ablation(figures["fig3d"]));
  if (!figures["fig4"].is_null()) drawn.push_back(GaltFigure(figures["fig4"]));
  return drawn;
}

Figure DrawHistogram(const std::string& name, const std::string& caption,
                     const std::vector<std::pair<std::string, std::vector<double>>>& series, double low, double high, int bins,
                     const std::string& unit, const std::optional<std::pair<double, std::string>>& marker) {
  const double left = 40, top = 20, width = 480, height = 140;
  Canvas canvas(static_cast<int>(left + width + 200), static_cast<int>(top + height + 30));
  std::vector<std::pair<std::string, std::vector<int>>> counts;
  for (const auto& [label, values] : series) counts.push_back({label, HistogramCounts(values, low, high, bins)});
  HistogramPanel(canvas, left, top, width, height, low, high, counts, unit);
  for (std::size_t s = 0; s < series.size(); ++s) {
    int outside = 0;
    for (const double value : series[s].second) outside += value >= low && value <= high ? 0 : 1;
    std::string legend = series[s].first + " (n = " + std::to_string(series[s].second.size());
    if (outside > 0) legend += ", " + std::to_string(outside) + " outside";
    canvas.Text(left + width + 10, top + 12 + 14 * static_cast<double>(s), legend + ")", 11, Canvas::Anchor::kStart, kColours[s % 6]);
  }
  if (marker && marker->first >= low && marker->first <= high) {
    const double x = XOf(marker->first, left, width, low, high);
    canvas.Line(x, top, x, top + height, "#d62728", 2.0, true, {{"marker", Num(marker->first)}});
    canvas.Text(x + 4, top + 10, marker->second, 10, Canvas::Anchor::kStart, "#d62728");
  }
  return {name, caption, std::move(canvas)};
}

}  // namespace tavis::batch::report

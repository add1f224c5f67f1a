#include "batch/report/figure_drawing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "batch/report/paper_figures.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

// Ten distinguishable colours (a figure with more series repeats them; its labels still name each).
const char* const kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
constexpr std::size_t kColourCount = sizeof(kColours) / sizeof(kColours[0]);
}  // namespace

const char* Colour(std::size_t i) { return kColours[i % kColourCount]; }

namespace {

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

}  // namespace

Canvas GroupedBars(const std::string& title, const std::vector<BarGroup>& groups,
                   const std::vector<std::string>& series) {
  constexpr double kValueSize = 8, kGroupSize = 10, kLegendSize = 11, kTitleSize = 13;
  const double left = 50, top = 40, height = 220, gap = 24;
  const double bar_width = std::max(24.0, Canvas::TextWidth("100.0", kValueSize) + 4);
  std::vector<double> group_widths;
  std::size_t label_lines = 1;
  double width = gap;
  for (const BarGroup& group : groups) {
    double group_width = bar_width * static_cast<double>(group.bars.size());
    for (const std::string& line : group.label)
      group_width = std::max(group_width, Canvas::TextWidth(line, kGroupSize) + 4);
    label_lines = std::max(label_lines, group.label.size());
    group_widths.push_back(group_width);
    width += group_width + gap;
  }
  width = std::max(width, 200.0);
  double legend_width = 0;
  for (const std::string& name : series) legend_width = std::max(legend_width, Canvas::TextWidth(name, kLegendSize));
  const double legend_left = left + width + 12;
  const double canvas_width =
      std::max(legend_left + 14 + legend_width + 10, left + Canvas::TextWidth(title, kTitleSize) + 10);
  Canvas canvas(std::max(640, static_cast<int>(std::ceil(canvas_width))),
                static_cast<int>(top + height + 14 * static_cast<double>(label_lines) + 16));
  canvas.Text(left, 18, title, kTitleSize);
  RateAxis(canvas, left, top, width, height);
  double x = left + gap;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const BarGroup& group = groups[g];
    const double bars_width = bar_width * static_cast<double>(group.bars.size());
    const double bars_left = x + (group_widths[g] - bars_width) / 2;
    for (std::size_t b = 0; b < group.bars.size(); ++b) {
      const Bar& bar = group.bars[b];
      const std::size_t s =
          static_cast<std::size_t>(std::find(series.begin(), series.end(), bar.series) - series.begin());
      const std::string colour = Colour(s);
      const double bx = bars_left + bar_width * static_cast<double>(b);
      if (bar.value.is_null()) {
        canvas.Text(bx + bar_width / 2, top + height - 3, "-", kGroupSize, Canvas::Anchor::kMiddle);
        continue;
      }
      const double mean = bar.value["mean"], spread = bar.value["std"];
      DataAttributes data = bar.data;
      data.push_back({"series", bar.series});
      data.push_back({"value", Num(mean)});
      data.push_back({"std", Num(spread)});
      canvas.Rect(bx + 1, top + height * (1.0 - mean), bar_width - 2, height * mean, colour, 0.85, colour, data);
      double label_y = top + height * (1.0 - mean) - 3;
      if (bar.value["checkpoints"].get<int>() > 1) {
        const double low = std::max(0.0, mean - spread), high = std::min(1.0, mean + spread);
        const double cx = bx + bar_width / 2;
        canvas.Line(cx, top + height * (1.0 - low), cx, top + height * (1.0 - high), "#222222", 1.5);
        label_y = std::min(label_y, top + height * (1.0 - high) - 3);  // above the whisker
      }
      canvas.Text(bx + bar_width / 2, label_y, PercentText(mean), kValueSize, Canvas::Anchor::kMiddle);
    }
    for (std::size_t line = 0; line < group.label.size(); ++line) {
      canvas.Text(x + group_widths[g] / 2, top + height + 15 + 13 * static_cast<double>(line), group.label[line],
                  kGroupSize, Canvas::Anchor::kMiddle);
    }
    x += group_widths[g] + gap;
  }
  for (std::size_t s = 0; s < series.size(); ++s) {
    const double y = top + 16 * static_cast<double>(s);
    canvas.Rect(legend_left, y, 10, 10, Colour(s), 0.85, "");
    canvas.Text(legend_left + 14, y + 9, series[s], kLegendSize);
  }
  return canvas;
}

namespace {

std::vector<std::string> GroupName(const Json& bar) {
  return {bar["robot"].get<std::string>(), bar["suite"].get<std::string>()};
}

// Label positions near `wanted` (ascending order not needed) that keep `spacing` apart and stay
// within [low, high]: equal rates (several tasks at 100 %) get a label each instead of one blot.
std::vector<double> SpreadLabels(const std::vector<double>& wanted, double spacing, double low, double high) {
  std::vector<std::size_t> order(wanted.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&wanted](std::size_t a, std::size_t b) { return wanted[a] < wanted[b]; });
  std::vector<double> placed(wanted.size());
  double previous = low - spacing;
  for (const std::size_t i : order) previous = placed[i] = std::max(wanted[i], previous + spacing);
  double next = high + spacing;  // then pull back from the bottom edge, keeping the spacing
  for (auto it = order.rbegin(); it != order.rend(); ++it) next = placed[*it] = std::min(placed[*it], next - spacing);
  return placed;
}

Figure HeadVsFixed(const Json& figure) {
  constexpr double kLabelSize = 9, kTitleSize = 13;
  std::vector<std::string> robots;
  double label_width = 0;
  for (const Json& point : figure["points"]) {
    if (std::find(robots.begin(), robots.end(), point["robot"]) == robots.end()) robots.push_back(point["robot"]);
    label_width = std::max(label_width, Canvas::TextWidth(point["task"].get<std::string>(), kLabelSize));
  }
  // A panel per robot: its rate axis (labels to the left, in the gap before it), the two camera
  // columns, then a column of task labels wide enough for the longest.
  const double axis_width = 200, label_gap = 24, panel_gap = 50, left = 50, top = 40, height = 240;
  const double panel = axis_width + label_gap + label_width + panel_gap;
  const std::string title =
      "Fig. 3a: head vs fixed camera, id split, per task (" + figure["policy"].get<std::string>() + ")";
  const double width =
      std::max(left + panel * static_cast<double>(robots.size()), left + Canvas::TextWidth(title, kTitleSize) + 10);
  Canvas canvas(std::max(640, static_cast<int>(std::ceil(width))), static_cast<int>(top + height + 50));
  canvas.Text(left, 18, title, kTitleSize);
  for (std::size_t r = 0; r < robots.size(); ++r) {
    const double x0 = left + panel * static_cast<double>(r);
    RateAxis(canvas, x0, top, axis_width, height);
    const double x_head = x0 + 40, x_fixed = x0 + axis_width - 40;
    canvas.Text(x_head, top + height + 16, "head", 11, Canvas::Anchor::kMiddle);
    canvas.Text(x_fixed, top + height + 16, "fixed", 11, Canvas::Anchor::kMiddle);
    canvas.Text(x0 + axis_width / 2, top + height + 32, robots[r], 12, Canvas::Anchor::kMiddle);
    std::vector<const Json*> points;
    std::vector<double> label_y;
    for (const Json& point : figure["points"]) {
      if (point["robot"] != robots[r]) continue;
      points.push_back(&point);
      label_y.push_back(top + height * (1.0 - point["fixed"]["mean"].get<double>()) + 3);
    }
    label_y = SpreadLabels(label_y, kLabelSize + 2, top + 3, top + height + 3);
    for (std::size_t t = 0; t < points.size(); ++t) {
      const Json& point = *points[t];
      const std::string colour = Colour(t);
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
      // The label in the column after the axis, led to its fixed-camera dot.
      const double label_x = x0 + axis_width + label_gap;
      canvas.Line(x_fixed + 5, y_fixed, label_x - 3, label_y[t] - 3, colour, 0.6);
      canvas.Text(label_x, label_y[t], point["task"].get<std::string>(), kLabelSize, Canvas::Anchor::kStart, colour);
    }
  }
  return {
      "fig3a_head_vs_fixed",
      "Figure 3a: success rate with the head camera and with the fixed camera, id split; a line per task pairs them",
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
    for (const std::string& split : splits)
      group.bars.push_back({split, bar[split], {{"suite", bar["suite"]}, {"robot", bar["robot"]}}});
    groups.push_back(group);
  }
  return {"fig3c_splits",
          "Figure 3c: suite means (head camera) of " + figure["policy"].get<std::string>() + " per split",
          GroupedBars("Fig. 3c: suite mean, head: id / ood-spatial / ood-init-pose (" +
                          figure["policy"].get<std::string>() + ")",
                      groups, splits)};
}

Figure Ablation(const Json& figure) {
  std::vector<BarGroup> groups;
  std::vector<std::string> series;
  BarGroup mean{{"mean over robots"}, {}};
  for (const Json& arm : figure["arms"]) {
    const std::string name = arm["arm"].get<std::string>() + " (" + arm["label"].get<std::string>() + ", " +
                             arm["task"].get<std::string>() + ", " + arm["camera"].get<std::string>() + ")";
    series.push_back(name);
    const Json value = arm["mean_over_robots"].is_null()
                           ? Json()
                           : Json({{"mean", arm["mean_over_robots"]}, {"std", 0.0}, {"checkpoints", 1}});
    mean.bars.push_back({name, value, {{"arm", arm["arm"]}, {"robot", "mean"}}});
  }
  groups.push_back(mean);
  // Every robot any arm evaluated (an arm the sweep lacks, e.g. no fixed-camera cells, has none).
  std::vector<std::string> robots;
  for (const Json& arm : figure["arms"]) {
    for (const Json& entry : arm["per_robot"]) {
      if (std::find(robots.begin(), robots.end(), entry["robot"]) == robots.end()) robots.push_back(entry["robot"]);
    }
  }
  for (const std::string& robot : robots) {
    BarGroup group{{robot}, {}};
    for (std::size_t a = 0; a < figure["arms"].size(); ++a) {
      Json value;
      for (const Json& entry : figure["arms"][a]["per_robot"]) {
        if (entry["robot"] == robot) value = entry["rate"];
      }
      group.bars.push_back({series[a], value, {{"arm", figure["arms"][a]["arm"]}, {"robot", robot}}});
    }
    groups.push_back(group);
  }
  return {"fig3d_ablation",
          "Figure 3d: the active-vision ablation, id split: no AV (fixed camera), full AV (head + wrists), wrist only "
          "(head blocked)",
          GroupedBars("Fig. 3d: no-AV / full-AV / wrist-only", groups, series)};
}

}  // namespace

std::vector<double> RoundTicks(double low, double high) {
  const double raw = (high - low) / 8.0;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10.0 * decade;
  for (const double factor : {1.0, 2.0, 5.0}) {
    if (factor * decade >= raw * (1 - 1e-9)) {
      step = factor * decade;
      break;
    }
  }
  std::vector<double> ticks;
  for (double k = std::ceil(low / step - 1e-9); k * step <= high + step * 1e-9; k += 1.0)
    ticks.push_back(k * step + 0.0);  // + 0.0: no "-0"
  return ticks;
}

void HistogramPanel(Canvas& canvas, double left, double top, double width, double height, double low, double high,
                    const std::vector<std::pair<std::string, std::vector<int>>>& series,
                    const std::string& axis_title) {
  const int bins = series.empty() ? 1 : static_cast<int>(series[0].second.size());
  int most = 1;
  for (const auto& [name, counts] : series) most = std::max(most, *std::max_element(counts.begin(), counts.end()));
  const double bottom = top + height;
  canvas.Line(left, bottom, left + width, bottom, "#333333");
  canvas.Line(left, top, left, bottom, "#333333");
  for (const double value : RoundTicks(low, high)) {
    const double x = left + width * (value - low) / (high - low);
    canvas.Line(x, bottom, x, bottom + 3, "#333333");
    canvas.Text(x, bottom + 13, Num(std::round(value * 1000) / 1000), 9, Canvas::Anchor::kMiddle);
  }
  canvas.Text(left + width / 2, bottom + 26, axis_title, 9, Canvas::Anchor::kMiddle);
  canvas.Line(left - 3, top, left, top, "#333333");
  canvas.Text(left - 5, top + 4, std::to_string(most), 9, Canvas::Anchor::kEnd);
  canvas.Text(left - 5, bottom, "0", 9, Canvas::Anchor::kEnd);  // clear of the first tick label below
  for (std::size_t s = 0; s < series.size(); ++s) {
    const std::string colour = Colour(s);
    const std::vector<int>& counts = series[s].second;
    double previous = bottom;
    for (int b = 0; b < bins; ++b) {
      const double x0 = left + width * b / bins, x1 = left + width * (b + 1) / bins;
      const double y = bottom - height * counts[static_cast<std::size_t>(b)] / most;
      canvas.Rect(x0, y, x1 - x0, bottom - y, colour, 0.2, "",
                  {{"series", series[s].first},
                   {"bin", std::to_string(b)},
                   {"low", Num(low + (high - low) * b / bins)},
                   {"high", Num(low + (high - low) * (b + 1) / bins)},
                   {"count", std::to_string(counts[static_cast<std::size_t>(b)])}});
      canvas.Line(x0, previous, x0, y, colour);
      canvas.Line(x0, y, x1, y, colour);
      previous = y;
    }
    canvas.Line(left + width, previous, left + width, bottom, colour);
  }
}

namespace {

double XOf(double value, double left, double width, double low, double high) {
  return left + width * (value - low) / (high - low);
}

std::string Seconds2(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f s", value);
  return text;
}

// A histogram's legend entry: "NAME (n = N, K outside the window)".
std::string CountText(const std::string& name, const Json& part) {
  std::string text = name + " (n = " + std::to_string(part["n"].get<int>());
  if (part["n_outside_window"].get<int>() > 0)
    text += ", " + std::to_string(part["n_outside_window"].get<int>()) + " outside the window";
  return text + ")";
}

Figure GaltFigure(const Json& figure) {
  constexpr double kTitleSize = 13, kPanelTitleSize = 11, kLegendSize = 10;
  const double low = figure["bins"]["low"], high = figure["bins"]["high"];
  const Json& tasks = figure["tasks"];
  const double panel_width = 480, panel_height = 130, left = 40, top = 56, pitch = panel_height + 80;
  const std::string reference = figure["reference"].is_null() ? "no reference" : figure["reference"].get<std::string>();
  char window[32];
  std::snprintf(window, sizeof(window), "%.1f", figure["window_s"].get<double>());
  const std::string title = "Fig. 4: GALT per TAVIS-Head task (id, head camera, successful episodes), window [-0.5, " +
                            std::string(window) + "] s";
  const std::string subtitle =
      figure["policy"].get<std::string>() + " (blue) vs " + reference + " (orange); dashed: medians";
  // Each panel's legend: per series its name, counts and median.
  std::vector<std::vector<std::pair<std::string, std::size_t>>> legends;
  double legend_width = 0;
  for (const Json& row : tasks) {
    std::vector<std::pair<std::string, std::size_t>> lines;
    std::size_t s = 0;
    for (const char* which : {"policy", "reference"}) {
      const Json& part = row[which];
      if (!part.is_null()) {
        const std::string name = std::string(which) == "policy"      ? figure["policy"].get<std::string>()
                                 : row["reference_source"].is_null() ? std::string("reference")
                                                                     : row["reference_source"].get<std::string>();
        lines.push_back({CountText(name, part), s});
        if (!part["median"].is_null()) lines.push_back({"median " + Seconds2(part["median"].get<double>()), s});
      }
      ++s;
    }
    for (const auto& [text, colour] : lines)
      legend_width = std::max(legend_width, Canvas::TextWidth(text, kLegendSize));
    legends.push_back(lines);
  }
  const double legend_left = left + panel_width + 14;
  const double width = std::max({legend_left + legend_width + 10, left + Canvas::TextWidth(title, kTitleSize) + 10,
                                 left + Canvas::TextWidth(subtitle, kPanelTitleSize) + 10});
  Canvas canvas(static_cast<int>(std::ceil(width)), static_cast<int>(top + pitch * static_cast<double>(tasks.size())));
  canvas.Text(left, 18, title, kTitleSize);
  canvas.Text(left, 36, subtitle, kPanelTitleSize);
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    const Json& row = tasks[t];
    const double y0 = top + pitch * static_cast<double>(t) + 20;
    std::vector<std::pair<std::string, std::vector<int>>> series = {
        {"policy", row["policy"]["counts"].get<std::vector<int>>()}};
    if (!row["reference"].is_null())
      series.push_back({"reference", row["reference"]["counts"].get<std::vector<int>>()});
    std::string panel_title = row["task"].get<std::string>() + ": n = " + std::to_string(row["policy"]["n"].get<int>());
    if (!row["reference"].is_null()) panel_title += " vs " + std::to_string(row["reference"]["n"].get<int>());
    if (!row["relative_median_difference"].is_null()) {
      char text[64];
      std::snprintf(text, sizeof(text), ", |delta median| / median = %.1f%%",
                    100.0 * row["relative_median_difference"].get<double>());
      panel_title += text;
    }
    canvas.Text(left, y0 - 8, panel_title, kPanelTitleSize);
    HistogramPanel(canvas, left, y0, panel_width, panel_height, low, high, series,
                   "GALT (s), " + Num(kGaltFigureBins) + " bins");
    int s = 0;
    for (const char* which : {"policy", "reference"}) {
      const Json& part = row[which];
      if (!part.is_null() && !part["median"].is_null()) {
        const double median = part["median"];
        const double x = XOf(median, left, panel_width, low, high);
        canvas.Line(x, y0, x, y0 + panel_height, Colour(static_cast<std::size_t>(s)), 2.0, true,
                    {{"series", which}, {"task", row["task"]}, {"median", Num(median)}});
      }
      ++s;
    }
    for (std::size_t line = 0; line < legends[t].size(); ++line) {
      canvas.Text(legend_left, y0 + 12 + 14 * static_cast<double>(line), legends[t][line].first, kLegendSize,
                  Canvas::Anchor::kStart, Colour(legends[t][line].second));
    }
  }
  return {"fig4_galt", "Figure 4: GALT per TAVIS-Head task, policy vs reference, 20 bins, medians dashed",
          std::move(canvas)};
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
                     const std::vector<std::pair<std::string, std::vector<double>>>& series, double low, double high,
                     int bins, const std::string& axis_title,
                     const std::optional<std::pair<double, std::string>>& marker) {
  constexpr double kLegendSize = 11;
  const double left = 40, top = 20, width = 480, height = 140;
  std::vector<std::pair<std::string, std::vector<int>>> counts;
  std::vector<std::string> legends;
  double legend_width = 0;
  for (const auto& [label, values] : series) {
    counts.push_back({label, HistogramCounts(values, low, high, bins)});
    int outside = 0;
    for (const double value : values) outside += value >= low && value <= high ? 0 : 1;
    std::string legend = label + " (n = " + std::to_string(values.size());
    if (outside > 0) legend += ", " + std::to_string(outside) + " outside";
    legends.push_back(legend + ")");
    legend_width = std::max(legend_width, Canvas::TextWidth(legends.back(), kLegendSize));
  }
  Canvas canvas(static_cast<int>(std::ceil(left + width + 14 + legend_width + 10)),
                static_cast<int>(top + height + 36));
  HistogramPanel(canvas, left, top, width, height, low, high, counts, axis_title);
  for (std::size_t s = 0; s < legends.size(); ++s) {
    canvas.Text(left + width + 14, top + 12 + 14 * static_cast<double>(s), legends[s], kLegendSize,
                Canvas::Anchor::kStart, Colour(s));
  }
  if (marker && marker->first >= low && marker->first <= high) {
    const double x = XOf(marker->first, left, width, low, high);
    canvas.Line(x, top, x, top + height, "#d62728", 2.0, true, {{"marker", Num(marker->first)}});
    canvas.Text(x + 4, top + 10, marker->second, 10, Canvas::Anchor::kStart, "#d62728");
  }
  return {name, caption, std::move(canvas)};
}

}  // namespace tavis::batch::report

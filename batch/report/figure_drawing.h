// The paper's figures drawn from summary["figures"] (paper_figures.h) on a Canvas: every bar,
// dot and histogram bin carries the number it shows as data-* attributes, so the SVG can be read
// back and compared with summary.json. Also the report's plain histograms, on an explicit range.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/svg_canvas.h"

namespace tavis::batch::report {

struct Figure {
  std::string name;     // file stem: figures/<name>.svg, .png; the SVG's id
  std::string caption;  // what it shows, for the report
  Canvas canvas;
};

// fig3a_head_vs_fixed, fig3b_single_vs_multi, fig3c_splits, fig3d_ablation, fig4_galt: those of
// the figures whose data is not null.
std::vector<Figure> DrawPaperFigures(const nlohmann::ordered_json& figures);

// Histograms of `series` (name, values) in `bins` equal bins on [low, high] as outlined steps, with
// an optional dashed vertical marker (position, label); `axis_title` names the values' axis (e.g.
// "GALT (s)"). Values outside [low, high] are not drawn; the legend counts them.
Figure DrawHistogram(const std::string& name, const std::string& caption,
                     const std::vector<std::pair<std::string, std::vector<double>>>& series, double low, double high,
                     int bins, const std::string& axis_title,
                     const std::optional<std::pair<double, std::string>>& marker);

// The parts the figures share (the paper's and the gaze figures, gaze_figures.h).

// The i-th of ten distinguishable series colours (repeated after ten).
const char* Colour(std::size_t i);

struct Bar {
  std::string series;            // legend name
  nlohmann::ordered_json value;  // {mean, std, checkpoints} or null (not evaluated)
  DataAttributes data;
};

struct BarGroup {
  std::vector<std::string> label;  // lines under the group
  std::vector<Bar> bars;
};

// Grouped bars of rates with their spread across checkpoints (when there are several) as
// whiskers, each bar's value above it; a legend of the series names in order. Bars, groups and the
// canvas are as wide as their labels need (Canvas::TextWidth), so no label overlaps another or
// runs off the canvas.
Canvas GroupedBars(const std::string& title, const std::vector<BarGroup>& groups,
                   const std::vector<std::string>& series);

// Tick positions on [low, high]: the multiples of the smallest step of 1, 2 or 5 x 10^k that gives
// at most about eight intervals (0.5 s on Figure 4's 4 s), so the labels are round numbers.
std::vector<double> RoundTicks(double low, double high);

// One step outline per series over the bins, each bin a data-carrying rectangle; axes with round
// labelled ticks (numbers only: `axis_title` names the unit below them) and the count scale (0 and
// the tallest bin).
void HistogramPanel(Canvas& canvas, double left, double top, double width, double height, double low, double high,
                    const std::vector<std::pair<std::string, std::vector<int>>>& series, const std::string& axis_title);

}  // namespace tavis::batch::report

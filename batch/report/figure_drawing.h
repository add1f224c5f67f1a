// The paper's figures drawn from summary["figures"] (paper_figures.h) on a Canvas: every bar,
// dot and histogram bin carries the number it shows as data-* attributes, so the SVG can be read
// back and compared with summary.json. Also the report's plain histograms, on an explicit range.
#pragma once

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

}  // namespace tavis::batch::report

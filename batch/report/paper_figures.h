// The numbers of the paper's Figure 3 (a-d), Figure 4 and headline numbers, computed from a
// sweep summary's per-label sections, so that the drawn figures (figure_drawing.h) and the
// summary hold the same numbers.
//
// Choices (spec["figures"]; every key optional; each names a policy label or a seed group, whose
// values are then the mean and spread across its checkpoints):
//   policy           the default for every panel (default: the first label)
//   head_vs_fixed    Fig. 3a: per robot and task, id split, head vs fixed, paired by a line
//   single_vs_multi  Fig. 3b: [single-task, multi-task]: suite means (id, head) per robot
//   splits           Fig. 3c: suite means (head) at id / ood-spatial / ood-init-pose per robot
//   ablation         Fig. 3d: {no_av, full_av, wrist_only: {label, task, camera}}, id split; by
//                    default the policy's clutter-pick-cube fixed, clutter-pick-cube head and
//                    blocked-clutter-pick-cube head cells (the paper's arms until camera sets exist)
//   galt             Fig. 4: the policy's GALT per TAVIS-Head task (id, head, successful episodes)
//   galt_reference   Fig. 4's reference: a label; otherwise the dataset's values given to the summary
//                    (the spec's galt_reference_datasets, read by sweep/galt_reference.h)
//   galt_window_s    values above it are left out of Fig. 4 (the detector keeps [-0.5, 4.0] s; the
//                    paper's figure uses 3.0, the default)
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tavis::batch::report {

// Figure 4's histogram: 20 bins from -0.5 s to 3.5 s (to the window when it is 4.0 s).
inline constexpr int kGaltFigureBins = 20;
inline constexpr double kGaltFigureLow = -0.5;
inline constexpr double kGaltFigureHigh = 3.5;
inline constexpr double kGaltFigureWindow = 3.0;

// summary["figures"]: {fig3a, fig3b, fig3c, fig3d, fig4}; a panel whose cells the sweep lacks is
// null. `galt_reference`: null or {source, tasks: {task: [seconds, ...]}, optionally datasets: {task:
// folder}}; each Fig. 4 row names its reference_source (the label, the task's folder or source).
nlohmann::ordered_json PaperFiguresJson(const nlohmann::ordered_json& summary, const nlohmann::ordered_json& choices,
                                        const nlohmann::ordered_json& galt_reference);

// summary["headline"]: the paper's headline numbers from the figures' data, each averaged over
// robots: q1_ablation (Fig. 3d's arms), q2_single_vs_multi (Fig. 3b per suite), q3_splits (Fig. 3c
// per suite). Fractions; null where the figure is.
nlohmann::ordered_json HeadlineJson(const nlohmann::ordered_json& figures);

// Counts of `values` in `bins` equal bins on [low, high]; values outside are not counted (the
// caller reports them), a value equal to high falls in the last bin.
std::vector<int> HistogramCounts(const std::vector<double>& values, double low, double high, int bins);

}  // namespace tavis::batch::report

// The gaze figures (docs/paper-figures.md, "Gaze figures"), computed from a sweep summary's "gaze"
// section (gaze_section.h) into summary["gaze_figures"] and drawn from it with the paper figures'
// machinery (figure_drawing.h), every bin, box and bar carrying its number as data-* attributes:
//   galt_verified   per task (id split, head camera, robots pooled): the histograms of the GALT
//                   values whose fixation at the grasp was on the target (verified) and of those
//                   whose was not, medians dashed
//   anchors         the anchor table drawn: per task, robot and anchor (id, head) the median and
//                   interquartile range of the lead time
//   gaze_on_target  the mean gaze-on-target ratio per task and robot (id split), a bar per policy
//                   label and camera
// The first two take the label (or seed group: its labels) spec["figures"]["gaze"] names, by
// default spec["figures"]["policy"], by default the first label; the third takes every label.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/figure_drawing.h"

namespace tavis::batch::report {

// The verified-vs-unverified histogram's bins: the detector's window, 0.25 s bins.
inline constexpr int kGazeGaltBins = 18;
inline constexpr double kGazeGaltLow = -0.5;
inline constexpr double kGazeGaltHigh = 4.0;

// summary["gaze_figures"]: {galt_verified, anchors, gaze_on_target}, each null when the sweep has
// no cells for it.
nlohmann::ordered_json GazeFiguresJson(const nlohmann::ordered_json& summary, const nlohmann::ordered_json& choices);

// gaze_galt_verified, gaze_anchors, gaze_on_target: those whose data is not null.
std::vector<Figure> DrawGazeFigures(const nlohmann::ordered_json& gaze_figures);

}  // namespace tavis::batch::report

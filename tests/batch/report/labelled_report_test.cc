// Labelled policies in the sweep summary: cells of different labels are never pooled; a seed
// group of checkpoints gives each rate's mean and spread across them; the paper's figures and
// headline numbers come from the labels' numbers, and the drawn figures carry those numbers; GALT
// values at the ends of the detector's window land in the right bins.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>
#include <string>

#include "batch/report/figure_drawing.h"
#include "batch/report/html_report.h"
#include "batch/report/paper_figures.h"
#include "batch/report/paper_table.h"
#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

// A cell of `label` with `successes` of `episodes` successful; head cells' successes get the
// GALT values in turn.
CellEpisodes Cell(const std::string& label, const std::string& task, const std::string& robot, CameraProtocol camera,
                  int successes, int episodes, const std::vector<double>& galt = {1.0},
                  const std::string& seed_group = "", scenarios::Split split = scenarios::Split::kId) {
  CellEpisodes cell;
  cell.config.task = task;
  cell.config.robot = robot;
  cell.config.split = split;
  cell.config.camera = camera;
  cell.config.policy = label == "still" ? "hold" : "expert";
  cell.label = label;
  cell.seed_group = seed_group;
  cell.id = task + "_" + robot + "_" + scenarios::ToString(split) + "_" + ToString(camera) + "_" + label + "_s0";
  for (int i = 0; i < episodes; ++i) {
    cell::EpisodeRecord record;
    record.episode = i;
    record.success = i < successes;
    record.length_steps = 60;
    if (record.success && camera == CameraProtocol::kHead) {
      kinematics::GaltResult result;
      result.reason = kinematics::GaltReason::kOk;
      result.galt_s = galt[static_cast<std::size_t>(i) % galt.size()];
      record.galt = result;
    }
    cell.episodes.push_back(record);
  }
  return cell;
}

const Json* FindSuite(const Json& summary, const std::string& label, const std::string& suite) {
  for (const Json& entry : summary["success"]) {
    if (entry["label"] == label && entry["suite"] == suite) return &entry;
  }
  return nullptr;
}

double TaskRate(const Json& summary, const std::string& label, const std::string& task, const std::string& camera) {
  const Json* suite = FindSuite(summary, label, "tavis-head");
  EXPECT_NE(suite, nullptr) << label;
  for (const Json& column : (*suite)["columns"]) {
    if (column["camera"] != camera) continue;
    for (const Json& row : column["tasks"]) {
      if (row["task"] == task) return row["success_rate"];
    }
  }
  ADD_FAILURE() << label << " " << task << " " << camera;
  return -1;
}

// Two labels that behave differently (expert 6/8 and 2/8 style counts vs hold 0/8) over 2 tasks x
// 2 cameras, on the same cells and seed.
std::vector<CellEpisodes> TwoLabels() {
  std::vector<CellEpisodes> cells;
  for (const char* task : {"clutter-pick-cube", "wait-then-act"}) {
    cells.push_back(Cell("expert", task, "gr1t2", CameraProtocol::kHead, 6, 8));
    cells.push_back(Cell("expert", task, "gr1t2", CameraProtocol::kFixed, 2, 8));
    cells.push_back(Cell("still", task, "gr1t2", CameraProtocol::kHead, 0, 8));
    cells.push_back(Cell("still", task, "gr1t2", CameraProtocol::kFixed, 1, 8));
  }
  return cells;
}

TEST(LabelledSummary, KeepsLabelsApart) {
  const Json summary = SweepSummaryJson({{"episodes", 8}}, TwoLabels());
  ASSERT_EQ(summary["labels"].size(), 2U);
  EXPECT_DOUBLE_EQ(TaskRate(summary, "expert", "wait-then-act", "head"), 6.0 / 8.0);
  EXPECT_DOUBLE_EQ(TaskRate(summary, "still", "wait-then-act", "head"), 0.0);
  EXPECT_DOUBLE_EQ(TaskRate(summary, "still", "clutter-pick-cube", "fixed"), 1.0 / 8.0);
  // Each label's pooled suite mean counts only its own 16 head episodes.
  for (const Json& entry : summary["success"]) {
    for (const Json& column : entry["columns"]) EXPECT_EQ(column["pooled"]["n_episodes"], 16) << entry["label"];
  }
  // Head vs fixed pairs within a label only: 2 tasks x 2 labels.
  ASSERT_EQ(summary["paired"].size(), 4U);
  EXPECT_EQ(summary["paired"][0]["label"], "expert");
  EXPECT_EQ(summary["paired"][0]["pairs"], 8);
  const std::vector<TextTable> tables = SweepTables(summary);
  ASSERT_EQ(tables[0].name, "success_tavis-head_expert");
  ASSERT_EQ(tables[1].name, "success_tavis-head_still");
  EXPECT_NE(ToMarkdown(tables[1]).find("| wait-then-act | 0.0 [0.0, 32.4] |"), std::string::npos)
      << ToMarkdown(tables[1]);
  // The cells name their labels.
  EXPECT_EQ(summary["cells"][2]["label"], "still");
  EXPECT_EQ(summary["cells"][2]["policy"], "hold");
}

TEST(LabelledSummary, SeedGroupGivesMeanAndSpreadAcrossCheckpoints) {
  std::vector<CellEpisodes> cells;
  const int successes[] = {2, 4, 9};  // of 12: rates 1/6, 1/3, 3/4
  for (int c = 0; c < 3; ++c) {
    const std::string label = "ckpt-" + std::to_string(c);
    cells.push_back(
        Cell(label, "clutter-pick-cube", "gr1t2", CameraProtocol::kHead, successes[c], 12, {1.0}, "recipe"));
    // A second evaluation seed of the same checkpoint pools into its rate: +0/12.
    CellEpisodes second = Cell(label, "clutter-pick-cube", "gr1t2", CameraProtocol::kHead, 0, 12, {1.0}, "recipe");
    second.config.seed = 1;
    second.id += "1";
    cells.push_back(second);
  }
  const Json summary = SweepSummaryJson({{"episodes", 12}}, cells);
  ASSERT_EQ(summary["seed_groups"].size(), 1U);
  const Json& group = summary["seed_groups"][0];
  EXPECT_EQ(group["labels"].size(), 3U);
  ASSERT_EQ(group["rows"].size(), 1U);
  const Json& row = group["rows"][0];
  const double rates[] = {2.0 / 24, 4.0 / 24, 9.0 / 24};
  const double mean = (rates[0] + rates[1] + rates[2]) / 3.0;
  double squared = 0.0;
  for (const double rate : rates) squared += (rate - mean) * (rate - mean);
  EXPECT_EQ(row["n"], 3);
  EXPECT_NEAR(row["mean"].get<double>(), mean, 1e-12);
  EXPECT_NEAR(row["std"].get<double>(), std::sqrt(squared / 2.0), 1e-12);
  EXPECT_NEAR(row["min"].get<double>(), rates[0], 1e-12);
  EXPECT_NEAR(row["max"].get<double>(), rates[2], 1e-12);
  // The suite mean row: one task evaluated, so the same numbers.
  ASSERT_EQ(group["suite_means"].size(), 1U);
  EXPECT_NEAR(group["suite_means"][0]["mean"].get<double>(), mean, 1e-12);
  bool printed = false;
  for (const TextTable& table : SweepTables(summary)) {
    if (table.name != "seed_groups") continue;
    printed = true;
    EXPECT_EQ(table.rows[0][7], Percent(mean));
  }
  EXPECT_TRUE(printed);
  // Figures take the group: its mean, with the spread drawn.
  const Json figures = PaperFiguresJson(summary, {{"splits", "recipe"}}, nullptr);
  EXPECT_NEAR(figures["fig3c"]["bars"][0]["id"]["mean"].get<double>(), mean, 1e-12);
  EXPECT_EQ(figures["fig3c"]["bars"][0]["id"]["checkpoints"], 3);
}

// Every data-* attribute set of the elements of `svg` that have `attribute`.
std::vector<std::map<std::string, std::string>> Marks(const std::string& svg, const std::string& attribute) {
  std::vector<std::map<std::string, std::string>> marks;
  const std::regex element("<(rect|circle|line)[^>]*>");
  const std::regex data("data-([a-z_]+)=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), element); it != std::sregex_iterator(); ++it) {
    const std::string text = it->str();
    std::map<std::string, std::string> values;
    for (auto d = std::sregex_iterator(text.begin(), text.end(), data); d != std::sregex_iterator(); ++d)
      values[(*d)[1]] = (*d)[2];
    if (values.count(attribute)) marks.push_back(values);
  }
  return marks;
}

TEST(PaperFigures, FiguresAndHeadlineFromTheLabelsNumbers) {
  std::vector<CellEpisodes> cells = TwoLabels();
  cells.push_back(Cell("expert", "blocked-clutter-pick-cube", "gr1t2", CameraProtocol::kHead, 7, 8));
  const Json spec = {{"episodes", 8},
                     {"figures", {{"single_vs_multi", {"still", "expert"}}, {"galt_reference", "still"}}}};
  const Json summary = SweepSummaryJson(spec, cells);
  const Json& figures = summary["figures"];
  // 3a: per task, head and fixed of the default policy (the first label).
  ASSERT_EQ(figures["fig3a"]["points"].size(), 2U);
  EXPECT_DOUBLE_EQ(figures["fig3a"]["points"][0]["head"]["mean"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(figures["fig3a"]["points"][0]["fixed"]["mean"].get<double>(), 0.25);
  // 3b: suite means, id head.
  EXPECT_DOUBLE_EQ(figures["fig3b"]["bars"][0]["single"]["mean"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(figures["fig3b"]["bars"][0]["multi"]["mean"].get<double>(), 0.75);
  // 3d: the default arms, clutter-pick-cube fixed / head, blocked-clutter-pick-cube head.
  const Json& arms = figures["fig3d"]["arms"];
  EXPECT_DOUBLE_EQ(arms[0]["mean_over_robots"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(arms[1]["mean_over_robots"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(arms[2]["mean_over_robots"].get<double>(), 7.0 / 8.0);
  EXPECT_DOUBLE_EQ(summary["headline"]["q1_ablation"]["wrist_only"].get<double>(), 7.0 / 8.0);
  EXPECT_DOUBLE_EQ(summary["headline"]["q2_single_vs_multi"][0]["multi"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(summary["headline"]["q3_splits"][0]["id"].get<double>(), 0.75);
  // The drawn figures carry the same numbers.
  for (const Figure& figure : DrawPaperFigures(figures)) {
    const std::string svg = figure.canvas.Svg(figure.name);
    if (figure.name == "fig3a_head_vs_fixed") {
      const auto dots = Marks(svg, "value");
      ASSERT_EQ(dots.size(), 4U);
      EXPECT_EQ(dots[0].at("task"), "clutter-pick-cube");
      EXPECT_DOUBLE_EQ(std::stod(dots[0].at("value")), 0.75);
      EXPECT_DOUBLE_EQ(std::stod(dots[1].at("value")), 0.25);
    }
    if (figure.name == "fig3d_ablation") {
      const auto bars = Marks(svg, "arm");
      ASSERT_EQ(bars.size(), 6U);  // mean over robots, then gr1t2
      EXPECT_EQ(bars[2].at("arm"), "wrist_only");
      EXPECT_DOUBLE_EQ(std::stod(bars[2].at("value")), 7.0 / 8.0);
    }
    EXPECT_GT(figure.canvas.Png().size(), 1000U) << figure.name;
    EXPECT_EQ(figure.canvas.Png().substr(1, 3), "PNG");
  }
  EXPECT_EQ(DrawPaperFigures(figures).size(), 5U);
  // Table 1: both columns of the expert label, the suite mean row.
  const std::string latex = PaperTable1Latex(summary, "expert");
  EXPECT_NE(latex.find("wait-then-act & 75.0 & 25.0 \\\\"), std::string::npos) << latex;
  EXPECT_NE(latex.find("\\textit{TAVIS-Head mean} & 75.0 & 25.0 \\\\"), std::string::npos) << latex;
  EXPECT_NE(latex.find("\\textit{TAVIS-Hands mean} & 87.5 & -- \\\\"), std::string::npos) << latex;
}

TEST(PaperFigures, GaltAtTheWindowsEndsLandInTheirBins) {
  // -0.45 s and +3.9 s: the first bin, and beyond Figure 4's 3.0 s window (in the last bin of the
  // 4.0 s window's [-0.5, 4.0]).
  const std::vector<double> values = {-0.45, 1.0, 1.2, 3.9};
  std::vector<CellEpisodes> cells = {
      Cell("expert", "clutter-pick-cube", "gr1t2", CameraProtocol::kHead, 4, 4, values),
      Cell("ref", "clutter-pick-cube", "gr1t2", CameraProtocol::kHead, 2, 2, {2.0, 2.4})};
  for (const double window : {3.0, 4.0}) {
    const Json spec = {{"episodes", 4}, {"figures", {{"galt_reference", "ref"}, {"galt_window_s", window}}}};
    const Json figure = SweepSummaryJson(spec, cells)["figures"]["fig4"];
    ASSERT_FALSE(figure.is_null());
    const Json& row = figure["tasks"][0];
    const std::vector<int> counts = row["policy"]["counts"];
    ASSERT_EQ(counts.size(), 20U);
    EXPECT_EQ(counts[0], 1) << "-0.45 s";
    EXPECT_EQ(row["policy"]["n"], window == 3.0 ? 3 : 4);
    EXPECT_EQ(row["policy"]["n_outside_window"], window == 3.0 ? 1 : 0);
    EXPECT_EQ(counts[19], window == 3.0 ? 0 : 1) << "3.9 s";
    EXPECT_DOUBLE_EQ(figure["bins"]["high"].get<double>(), window == 3.0 ? 3.5 : 4.0);
    const double median = window == 3.0 ? 1.0 : 1.1;
    EXPECT_DOUBLE_EQ(row["policy"]["median"].get<double>(), median);
    EXPECT_DOUBLE_EQ(row["reference"]["median"].get<double>(), 2.2);
    EXPECT_NEAR(row["relative_median_difference"].get<double>(), std::abs(median - 2.2) / 2.2, 1e-12);
    // Drawn: the bins' counts and the medians read back from the SVG.
    const Json figures = {
        {"fig3a", nullptr}, {"fig3b", nullptr}, {"fig3c", nullptr}, {"fig3d", nullptr}, {"fig4", figure}};
    const std::string svg = DrawPaperFigures(figures).at(0).canvas.Svg("fig4");
    int policy_total = 0;
    for (const auto& bin : Marks(svg, "count")) {
      if (bin.at("series") == "policy") policy_total += std::stoi(bin.at("count"));
    }
    EXPECT_EQ(policy_total, row["policy"]["n"].get<int>());
    const auto medians = Marks(svg, "median");
    ASSERT_EQ(medians.size(), 2U);
    EXPECT_DOUBLE_EQ(std::stod(medians[0].at("median")), median);
  }
  // The report's plain histograms: values outside the range are left out and counted, never
  // written outside the bins (this ran past the buffer before).
  const Figure histogram =
      DrawHistogram("h", "h", {{"galt", values}}, -0.5, 4.0, 18, "s", std::make_pair(2.57, "human"));
  int total = 0;
  for (const auto& bin : Marks(histogram.canvas.Svg("h"), "count")) total += std::stoi(bin.at("count"));
  EXPECT_EQ(total, 4);
  const Figure narrow = DrawHistogram("n", "n", {{"galt", values}}, 0.0, 3.0, 12, "s", std::nullopt);
  total = 0;
  for (const auto& bin : Marks(narrow.canvas.Svg("n"), "count")) total += std::stoi(bin.at("count"));
  EXPECT_EQ(total, 2);
  EXPECT_NE(narrow.canvas.Svg("n").find("2 outside"), std::string::npos);
  EXPECT_EQ(HistogramCounts({-0.5, 3.5, -0.51, 3.51}, -0.5, 3.5, 20),
            (std::vector<int>{1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}));
}

struct TextBox {
  std::string text;
  double left, right, top, bottom;
};

// Every <text> of `svg` with the box it is drawn in: as wide as Canvas::TextWidth measures it (the
// PNG's font or a browser's sans-serif, the wider), from the baseline up by its font size.
std::vector<TextBox> TextBoxes(const std::string& svg) {
  std::vector<TextBox> boxes;
  const std::regex text(
      "<text x=\"([-0-9.e]+)\" y=\"([-0-9.e]+)\" font-size=\"([0-9.e]+)\" "
      "text-anchor=\"([a-z]+)\"[^>]*>([^<]*)</text>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), text); it != std::sregex_iterator(); ++it) {
    const double x = std::stod((*it)[1]), y = std::stod((*it)[2]), size = std::stod((*it)[3]);
    const std::string content = std::regex_replace((*it)[5].str(), std::regex("&amp;"), "&");
    const double width = Canvas::TextWidth(content, size);
    const double left = (*it)[4] == "start" ? x : (*it)[4] == "middle" ? x - width / 2 : x - width;
    boxes.push_back({content, left, left + width, y - size, y});
  }
  return boxes;
}

// The figures' labels stay on their canvas and never overlap: bar values over narrow bars, group
// names, Fig. 3a's task labels of equal rates (both tasks at 75 % / 25 % here), legends, titles.
TEST(PaperFigures, LabelsNeitherOverlapNorLeaveTheCanvas) {
  std::vector<CellEpisodes> cells = TwoLabels();
  cells.push_back(Cell("expert", "blocked-clutter-pick-cube", "gr1t2", CameraProtocol::kHead, 7, 8));
  for (CellEpisodes cell : TwoLabels()) {  // a second robot, for more groups and panels
    cell.config.robot = "reachy2";
    cell.id += "_reachy2";
    cells.push_back(cell);
  }
  const Json spec = {{"episodes", 8},
                     {"figures", {{"single_vs_multi", {"still", "expert"}}, {"galt_reference", "still"}}}};
  const std::vector<Figure> figures = DrawPaperFigures(SweepSummaryJson(spec, cells)["figures"]);
  ASSERT_EQ(figures.size(), 5U);
  for (const Figure& figure : figures) {
    const std::vector<TextBox> boxes = TextBoxes(figure.canvas.Svg(figure.name));
    ASSERT_GT(boxes.size(), 5U) << figure.name;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const TextBox& a = boxes[i];
      EXPECT_GE(a.left, 0.0) << figure.name << ": '" << a.text << "'";
      EXPECT_LE(a.right, figure.canvas.width()) << figure.name << ": '" << a.text << "'";
      EXPECT_GE(a.top, 0.0) << figure.name << ": '" << a.text << "'";
      EXPECT_LE(a.bottom, figure.canvas.height()) << figure.name << ": '" << a.text << "'";
      for (std::size_t j = i + 1; j < boxes.size(); ++j) {
        const TextBox& b = boxes[j];
        const bool overlap = a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
        EXPECT_FALSE(overlap) << figure.name << ": '" << a.text << "' and '" << b.text << "'";
      }
    }
  }
}

// Fig. 3d of a sweep without fixed-camera cells: no no-AV arm, yet every robot's other arms drawn.
TEST(PaperFigures, AblationDrawsEveryRobotOfTheArmsPresent) {
  const std::vector<CellEpisodes> cells = {Cell("expert", "clutter-pick-cube", "gr1t2", CameraProtocol::kHead, 3, 4),
                                           Cell("expert", "clutter-pick-cube", "reachy2", CameraProtocol::kHead, 1, 4)};
  const Json figures = SweepSummaryJson({{"episodes", 4}}, cells)["figures"];
  ASSERT_FALSE(figures["fig3d"].is_null());
  const Json only = {
      {"fig3a", nullptr}, {"fig3b", nullptr}, {"fig3c", nullptr}, {"fig3d", figures["fig3d"]}, {"fig4", nullptr}};
  const auto bars = Marks(DrawPaperFigures(only).at(0).canvas.Svg("fig3d"), "arm");
  std::map<std::string, double> full_av;
  for (const auto& bar : bars) {
    EXPECT_EQ(bar.at("arm"), "full_av") << "only the full-AV arm has cells";
    full_av[bar.at("robot")] = std::stod(bar.at("value"));
  }
  EXPECT_EQ(full_av.size(), 3U);  // the mean over robots, gr1t2, reachy2
  EXPECT_DOUBLE_EQ(full_av["gr1t2"], 0.75);
  EXPECT_DOUBLE_EQ(full_av["reachy2"], 0.25);
  EXPECT_DOUBLE_EQ(full_av["mean"], 0.5);
}

// The SVG with id `id` inside an HTML page (empty when absent).
std::string SvgById(const std::string& html, const std::string& id) {
  const std::size_t start = html.find("<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" + id + "\"");
  if (start == std::string::npos) return "";
  return html.substr(start, html.find("</svg>", start) + 6 - start);
}

// Every histogram of the report page, end to end from the summary: Figure 4 (3.0 s window) and
// the per-label, per-robot GALT histograms on the detector's [-0.5, 4.0] s. -0.45 s and +3.9 s
// land in the first and last bins, or are counted outside; nothing is drawn off its axis. This
// runs in the sanitizer job (.ci/sanitize, tavis_report_tests), where the old histogram's write
// before its first bin was a heap-buffer-overflow.
TEST(PaperFigures, ReportHistogramsDrawGaltAtBothEnds) {
  const std::vector<double> values = {-0.45, 1.0, 1.2, 3.9};
  const std::vector<CellEpisodes> cells = {
      Cell("expert", "clutter-pick-cube", "gr1t2", CameraProtocol::kHead, 4, 4, values),
      Cell("ref", "clutter-pick-cube", "gr1t2", CameraProtocol::kHead, 2, 2, {-0.45, 3.9})};
  const Json summary = SweepSummaryJson({{"episodes", 4}, {"figures", {{"galt_reference", "ref"}}}}, cells);
  const std::string html = SweepHtmlReport(summary, Json::object());
  // The per-robot histogram of the expert: 18 bins of 0.25 s from -0.5 s.
  const std::string robot = SvgById(html, "galt_expert_gr1t2");
  ASSERT_FALSE(robot.empty()) << html;
  std::vector<int> counts;
  for (const auto& bin : Marks(robot, "count")) counts.push_back(std::stoi(bin.at("count")));
  ASSERT_EQ(counts.size(), 18U);
  EXPECT_EQ(counts[0], 1) << "-0.45 s";
  EXPECT_EQ(counts[17], 1) << "3.9 s";
  EXPECT_EQ(counts[6], 2) << "1.0 s and 1.2 s";
  const auto first = Marks(robot, "count").front();
  EXPECT_DOUBLE_EQ(std::stod(first.at("low")), -0.5);
  // Figure 4 in the page: 3.9 s lies beyond the 3.0 s window (counted, not drawn) for both series.
  const std::string figure = SvgById(html, "fig4_galt");
  ASSERT_FALSE(figure.empty());
  std::map<std::string, std::vector<int>> series;
  for (const auto& bin : Marks(figure, "count")) series[bin.at("series")].push_back(std::stoi(bin.at("count")));
  ASSERT_EQ(series["policy"].size(), 20U);
  ASSERT_EQ(series["reference"].size(), 20U);
  EXPECT_EQ(series["policy"][0], 1);
  EXPECT_EQ(series["reference"][0], 1);
  EXPECT_EQ(series["policy"][19] + series["reference"][19], 0);
  EXPECT_EQ(summary["figures"]["fig4"]["tasks"][0]["reference"]["n_outside_window"], 1);
  // Every drawn bin lies within its panel: no rectangle of negative size or left of the axis.
  const std::regex rect("<rect x=\"([-0-9.e]+)\" y=\"([-0-9.e]+)\" width=\"([-0-9.e]+)\" height=\"([-0-9.e]+)\"");
  for (const std::string& svg : {robot, figure}) {
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), rect); it != std::sregex_iterator(); ++it) {
      EXPECT_GE(std::stod((*it)[1]), 0.0) << it->str();
      EXPECT_GE(std::stod((*it)[3]), 0.0) << it->str();
      EXPECT_GE(std::stod((*it)[4]), 0.0) << it->str();
    }
  }
}

}  // namespace
}  // namespace tavis::batch::report

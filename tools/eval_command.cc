// `tavis eval`: one evaluation cell, written to DIR/episodes.jsonl and DIR/summary.json, or one
// cell per task of a suite.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "batch/atomic_file.h"
#include "batch/cell_profile.h"
#include "batch/cell_record_stream.h"
#include "batch/cell_report.h"
#include "batch/evaluation_cell.h"
#include "batch/remote/observation_keys.h"
#include "batch/scene_render.h"
#include "scenarios/registry.h"
#include "tools/commands.h"
#include "tools/option_parsing.h"
#include "tools/progress_reporter.h"

namespace tavis::tools {
namespace {

struct EvalOptions {
  batch::EvaluationCellConfig cell;
  std::string split = "id";
  std::string camera = "head";
  std::string out;
  std::string render_cameras;
  std::string image_size;
  std::string suite;
  bool task_given = false;
  bool image_size_given = false;
  int threads = 0;
  bool quiet = false;
  bool overwrite = false;
  bool resume = false;
};

std::string DefaultCellDirName(const batch::EvaluationCellConfig& cell, const std::string& split) {
  return cell.task + "_" + cell.robot + "_" + split + "_" + batch::ToString(cell.camera) + "_" + cell.policy + "_s" +
         std::to_string(cell.seed);
}

// One cell into `out`: its records streamed as episodes end (an interrupted cell keeps them and
// --resume continues after them), the summary written last.
batch::CellResult RunCell(const batch::EvaluationCellConfig& cell, const EvalOptions& options, int threads,
                          const std::string& out) {
  if (out.empty()) throw std::invalid_argument("--out must name a folder");
  batch::CheckEvaluationCell(cell);  // a bad setting must not touch what --out holds
  if (options.overwrite && std::filesystem::exists(out)) std::filesystem::remove_all(out);
  const bool created = !std::filesystem::exists(out);
  batch::CellRecordStream stream(out, cell, options.resume);
  batch::EvaluationCellConfig config = cell;
  config.first_episode = stream.next_episode();
  batch::CellResult result;
  ProgressReporter reporter(stderr, ProgressReporter::StyleFor(stderr));
  const batch::ProgressCallback progress = [&reporter](int64_t done, int64_t total) { reporter.Update("", done, total); };
  try {
    result = batch::RunEvaluationCell(config, options.quiet ? batch::ProgressCallback() : progress,
                                      [&stream](const batch::EpisodeRecord& record) { stream.Write(record); });
  } catch (...) {
    // A cell that failed before its first episode leaves nothing behind; one that recorded
    // episodes keeps them for --resume.
    if (created && stream.written() == 0) std::filesystem::remove_all(out);
    throw;
  }
  // The summary covers the whole cell: the resumed records first.
  std::vector<batch::EpisodeRecord> episodes = stream.resumed();
  for (batch::EpisodeRecord& record : result.episodes) episodes.push_back(std::move(record));
  result.episodes = std::move(episodes);
  result.successes = 0;
  for (const batch::EpisodeRecord& record : result.episodes) result.successes += record.success ? 1 : 0;
  batch::WriteCellSummary(result, {threads, stream.next_episode()}, out);
  std::cout << batch::CellSummaryLine(result) << " -> " << out << "\n";
  if (result.profile) {
    std::cout << batch::FormatCellProfile(*result.profile);
    batch::WriteFileAtomically(out + "/profile.json", batch::CellProfileJson(*result.profile));
  }
  return result;
}

// Every task of the suite, one cell each in OUT/<task>_<robot>_<split>_<camera>_<policy>_s<seed>, then the
// suite mean as the paper reports it (task average) and pooled over episodes. A task without a
// scripted expert is reported and makes the exit status 1; the others still run.
void RunSuite(batch::EvaluationCellConfig cell, const EvalOptions& options, int threads) {
  std::vector<std::string> tasks;
  for (const scenarios::ScenarioDef* scenario : scenarios::SuiteScenarios(scenarios::ParseSuite(options.suite))) {
    tasks.push_back(scenario->name);
  }
  const std::string base = options.out.empty() ? "results/" + options.suite : options.out;
  double rate_sum = 0.0;
  int cells = 0, successes = 0, episodes = 0;
  std::vector<std::string> failed;
  for (const std::string& task : tasks) {
    cell.task = task;
    try {
      const batch::CellResult result = RunCell(cell, options, threads, base + "/" + DefaultCellDirName(cell, options.split));
      rate_sum += static_cast<double>(result.successes) / static_cast<double>(result.episodes.size());
      successes += result.successes;
      episodes += static_cast<int>(result.episodes.size());
      ++cells;
    } catch (const std::invalid_argument& error) {
      std::cout << task << ": not run: " << error.what() << "\n";
      failed.push_back(task);
    }
  }
  if (cells > 0) {
    std::printf("%s %s %s policy=%s camera=%s: suite mean over %d tasks %.1f%% (task average), %.1f%% pooled (%d/%d)\n",
                options.suite.c_str(), cell.robot.c_str(), options.split.c_str(), cell.policy.c_str(),
                batch::ToString(cell.camera), cells,
                100.0 * rate_sum / cells, 100.0 * successes / episodes, successes, episodes);
  }
  if (!failed.empty()) {
    std::string names;
    for (const std::string& task : failed) names += (names.empty() ? "" : ", ") + task;
    throw std::runtime_error("suite incomplete: " + names + " not run");
  }
}

void RunEval(const EvalOptions& options) {
  batch::EvaluationCellConfig cell = options.cell;
  cell.split = scenarios::ParseSplit(options.split);
  cell.camera = batch::ParseCameraProtocol(options.camera);
  if (!options.render_cameras.empty()) cell.render_cameras = batch::ParseCameraList(options.render_cameras);
  if (options.image_size_given) std::tie(cell.image_width, cell.image_height) = ParseImageSize(options.image_size);
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  if (options.overwrite && options.resume) throw std::invalid_argument("give --overwrite or --resume, not both");
  if (!options.suite.empty()) {
    if (options.task_given) throw std::invalid_argument("give either --task or --suite, not both");
    RunSuite(cell, options, threads);
    return;
  }
  scenarios::FindScenario(cell.task);  // fail fast on an unknown task, before any work
  RunCell(cell, options, threads, options.out.empty() ? "results/" + DefaultCellDirName(cell, options.split) : options.out);
}

}  // namespace

void RegisterEvalCommand(CLI::App& app) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* eval = app.add_subcommand(
      "eval", "Run one evaluation cell: N episodes of a task with a policy, batched over parallel envs.\n"
              "Writes DIR/episodes.jsonl (one JSON object per episode) and DIR/summary.json (success\n"
              "rate with its 95% Wilson interval, wall time, throughput).");
  eval->add_option("--task", options->cell.task, "Task (" + scenarios::KnownTasks() + ")")->capture_default_str();
  eval->add_option("--suite", options->suite,
                   "Run every task of a suite instead of one task: " + scenarios::KnownSuites() + "; cells go to\n"
                   "OUT/<task>_<robot>_<split>_<camera>_<policy>_s<seed> (OUT defaults to results/<suite>), then the\n"
                   "suite mean is printed as a task average and pooled over episodes");
  eval->add_option("--robot", options->cell.robot, "Robot: gr1t2 or reachy2 (configs/robots/<name>.yaml)")
      ->capture_default_str();
  eval->add_option("--split", options->split, "Split: id, ood-spatial or ood-init-pose")->capture_default_str();
  eval->add_option("--camera", options->camera,
                   "Camera protocol: head (the policy sees and moves the head camera; GALT computed) or fixed\n"
                   "(the fixed camera instead, neck actions and neck state zeroed, no GALT); episode i has the\n"
                   "same scene under both, so a head and a fixed cell pair")
      ->capture_default_str();
  eval->add_option("--policy", options->cell.policy,
                   "Policy (" + batch::CellPolicyNames() + "); openpi: a policy served over openpi's websocket\n"
                   "protocol (--server), acting at 20 Hz on the cameras its --keys name")
      ->capture_default_str();
  eval->add_option("--server", options->cell.servers,
                   "For --policy openpi: ws://HOST:PORT of a policy server; repeat it to spread the env slots over\n"
                   "several servers (slot i asks server i mod K). Each episode's actions are saved in\n"
                   "DIR/actions/episode_<i>.csv for --policy replay");
  eval->add_option("--replan-steps", options->cell.replan_steps,
                   "For --policy openpi: rows of each action chunk an env steps with before asking again\n"
                   "(0: the whole chunk, as openpi's ActionChunkBroker; its LIBERO example uses 5)")
      ->check(IntegerIn(0, 1000000))
      ->capture_default_str();
  eval->add_option("--keys", options->cell.observation_keys,
                   "For --policy openpi: the request's key layout, a preset (" + remote::KeyPresetNames() + ") or a\n"
                   "YAML file of that schema (configs/policy_keys/*.yaml: keys per camera, state and prompt,\n"
                   "hwc/chw images, image size, letterbox)")
      ->capture_default_str();
  eval->add_option("--server-timeout", options->cell.server_ready_timeout_s,
                   "For --policy openpi: seconds to wait for each server's /healthz before giving up")
      ->check(NumberIn(0.001, 86400))
      ->capture_default_str();
  eval->add_option("--actions", options->cell.actions_file,
                   "For --policy replay: T x 19 CSV of canonical actions, one row per 20 Hz step");
  eval->add_option("--episodes", options->cell.episodes, "Episodes in the cell")
      ->check(IntegerIn(1, 100000000))
      ->capture_default_str();
  AddSeedOption(*eval, options->cell.seed, "Seed: episode i draws its randomness from (seed, i)");
  eval->add_option("--envs", options->cell.envs, "Parallel env slots stepped lock-step, for a served policy or rendering; a built-in policy\n"
                   "without rendering runs one slot per thread instead (results do not depend on it)")
      ->check(IntegerIn(1, 4096))
      ->capture_default_str();
  eval->add_option("--threads", options->threads, "Worker threads (0 = all cores; results do not depend on it)")
      ->check(IntegerIn(0, 1024))
      ->capture_default_str();
  eval->add_option("--render-cameras", options->render_cameras,
                   "Comma-separated cameras to render on every policy tick (20 Hz) even if the policy uses no\n"
                   "images, e.g. head,left_wrist,right_wrist (known: head, fixed, left_wrist, right_wrist); the\n"
                   "images are discarded: for measuring throughput with rendering");
  eval->add_option("--image-size", options->image_size,
                   "Size of the policy's images, WIDTHxHEIGHT (default: the observation keys' size for --policy\n"
                   "openpi, 224x224 in the presets; otherwise the reference's 640x480)");
  eval->add_option("--out", options->out, "Output directory (default results/<task>_<robot>_<split>_<camera>_<policy>_s<seed>)");
  AddConfigDirOption(*eval, options->cell.config_dir);
  eval->add_flag("--quiet", options->quiet, "No progress (episodes done, rate, ETA; a status line on a terminal, else a line per tenth)");
  eval->add_flag("--profile", options->cell.profile,
                 "Time every stage (actions/IK, physics, neck, task, reset, render, policy, recording) and\n"
                 "episode; print the shares, the critical path (unlimited threads) and thread-count\n"
                 "estimates, and write DIR/profile.json");
  eval->add_flag("--overwrite", options->overwrite, "Replace the results already in --out");
  eval->add_flag("--resume", options->resume,
                 "Finish an interrupted cell in --out (same settings): its complete episodes are kept, the rest run");
  eval->callback([options, eval] {
    // Refused rather than ignored: a cell's files must come from the options its command names.
    if (eval->count("--out") > 0 && options->out.empty()) {
      throw std::invalid_argument("--out must name a folder, got an empty string");
    }
    if (eval->count("--actions") > 0 && options->cell.policy != "replay") {
      throw std::invalid_argument("--actions '" + options->cell.actions_file + "' applies to --policy replay only, got --policy " +
                                  options->cell.policy);
    }
    options->task_given = eval->count("--task") > 0;
    options->image_size_given = eval->count("--image-size") > 0;
    RunEval(*options);
  });
}

}  // namespace tavis::tools

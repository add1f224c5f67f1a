// `tavis verify DIR`: re-simulates every cell under DIR from its saved actions and compares the
// records (batch/cell/cell_verification.h); DIR may be a submission (batch/cell/submission_card.h),
// whose card is checked first. Exit status 0 when every cell verifies, 1 when a record or a config
// differs (or a cell does not match the card), 2 when a cell cannot be verified (none found, no
// actions, unreadable files) or the card is malformed.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "batch/cell/cell_verification.h"
#include "batch/cell/submission_card.h"
#include "batch/output/atomic_file.h"
#include "batch/output/output_folder.h"
#include "batch/output/program_version.h"
#include "tools/commands.h"
#include "tools/exit_status.h"
#include "tools/option_parsing.h"
#include "tools/progress_reporter.h"

namespace tavis::tools {
namespace {

namespace fs = std::filesystem;

constexpr int kCannotVerifyStatus = 2;
using batch::cell::CellVerification;
using batch::cell::VerifyOutcome;

struct VerifyOptions {
  std::string dir;
  std::string config_dir;
  std::string json_out;
  int threads = 0;
  bool skip_unverifiable = false;
  bool quiet = false;
};

// What the cells came to, for the summary line, --json and the exit status.
struct Tally {
  int ok = 0, failed = 0, skipped = 0, unreadable = 0;
  int64_t episodes = 0, identical = 0;
  std::vector<std::string> no_actions;  // the cells that have none
  std::map<std::string, int> versions;  // recorded program versions other than this one, with their cells
  nlohmann::json cells = nlohmann::json::array();

  int ExitStatus(bool skip_unverifiable) const {
    if (failed > 0) return 1;
    return unreadable > 0 || (!skip_unverifiable && skipped > 0) ? 2 : 0;
  }
};

std::string CellName(const fs::path& cell, const fs::path& dir) {
  return cell == dir ? dir.string() : fs::relative(cell, dir).string();
}

void Count(const CellVerification& verification, const std::string& name, Tally& tally) {
  tally.cells.push_back(batch::cell::VerificationJson(verification, name));
  if (verification.outcome == VerifyOutcome::kNoActions) {
    ++tally.skipped;
    tally.no_actions.push_back(name);
    return;
  }
  ++(verification.outcome == VerifyOutcome::kIdentical ? tally.ok : tally.failed);
  tally.episodes += verification.episodes;
  tally.identical += verification.identical;
  if (verification.program_version_differs()) ++tally.versions[verification.program_version_recorded];
}

std::string SummaryLine(const Tally& tally, std::size_t cells, const VerifyOptions& options) {
  std::string line = "verify " + options.dir + ": " + std::to_string(cells) + " cells, " + std::to_string(tally.ok) +
                     " ok, " + std::to_string(tally.failed) + " FAIL, " + std::to_string(tally.skipped) +
                     " without actions" + (options.skip_unverifiable ? " (skipped)" : "") + ", " +
                     std::to_string(tally.unreadable) + " unreadable; " + std::to_string(tally.identical) + "/" +
                     std::to_string(tally.episodes) + " episodes identical";
  if (!tally.no_actions.empty()) {
    line += "\nwithout actions:";
    for (const std::string& name : tally.no_actions) line += " " + name;
  }
  return line;
}

int Verify(const VerifyOptions& options) {
  const fs::path dir = options.dir;
  if (!options.json_out.empty() && batch::output::IsSameOrInside(options.json_out, dir))
    throw std::invalid_argument("--json " + options.json_out + " is inside " + options.dir +
                                ": verify writes nothing there; give a file elsewhere");
  // A submission's card is checked first (a bad field exits 2, naming it); its cells are those of
  // its results folder.
  std::optional<batch::cell::SubmissionCard> card;
  if (batch::cell::IsSubmission(dir)) {
    card = batch::cell::ReadSubmissionCard(dir);
    std::cout << "submission " << options.dir << ": " << card->model << " " << card->version << " ("
              << card->policy_family << "), results " << fs::relative(card->results, dir).string() << std::endl;
  }
  const fs::path results = card ? card->results : dir;
  const std::vector<fs::path> cells = batch::cell::FindCells(results);
  if (cells.empty())
    throw std::invalid_argument("no cell found under " + results.string() + " (no cell.json at any depth)");
  int64_t total = 0;
  for (const fs::path& cell : cells) total += batch::cell::RecordedEpisodeCount(cell);
  ProgressReporter reporter(stderr, ProgressReporter::StyleFor(stderr));
  batch::cell::VerifySettings settings;
  settings.config_dir = options.config_dir;
  int64_t done_before = 0;
  if (!options.quiet)
    settings.progress = [&](int64_t done, int64_t) {
      reporter.Update("", done_before + done, std::max(total, done_before + done));
    };
  Tally tally;
  for (const fs::path& cell : cells) {
    const std::string name = CellName(cell, dir);
    try {
      const std::string mismatch = card ? batch::cell::CardMismatch(*card, cell) : "";
      if (!mismatch.empty()) {
        std::cout << "FAIL " << name << ": does not match the submission card: " << mismatch << std::endl;
        tally.cells.push_back({{"cell", name}, {"path", cell.string()}, {"outcome", "fail"}, {"card", mismatch}});
        ++tally.failed;
        done_before += batch::cell::RecordedEpisodeCount(cell);
        continue;
      }
      const CellVerification verification = batch::cell::VerifyCell(cell, settings);
      std::cout << batch::cell::VerificationLine(verification, name) << std::endl;
      Count(verification, name, tally);
    } catch (const std::exception& error) {
      std::cout << "ERR  " << name << ": cannot verify: " << error.what() << std::endl;
      tally.cells.push_back(
          {{"cell", name}, {"path", cell.string()}, {"outcome", "unreadable"}, {"error", error.what()}});
      ++tally.unreadable;
    }
    done_before += batch::cell::RecordedEpisodeCount(cell);
  }
  for (const auto& [version, count] : tally.versions) {
    std::cerr << "warning: " << count << " cell(s) were recorded by tavis " << version << ", verified with tavis "
              << batch::output::ProgramVersion() << " (a warning: their records were compared all the same)\n";
  }
  std::cout << SummaryLine(tally, cells.size(), options) << std::endl;
  const int status = tally.ExitStatus(options.skip_unverifiable);
  if (!options.json_out.empty()) {
    nlohmann::json report = {{"dir", options.dir},
                             {"program_version", batch::output::ProgramVersion()},
                             {"cells", tally.cells},
                             {"summary",
                              {{"cells", cells.size()},
                               {"ok", tally.ok},
                               {"failed", tally.failed},
                               {"no_actions", tally.skipped},
                               {"unreadable", tally.unreadable},
                               {"episodes", tally.episodes},
                               {"identical", tally.identical}}},
                             {"exit_status", status}};
    if (card) report["submission"] = card->json;
    batch::output::WriteFileAtomically(options.json_out, report.dump(2) + "\n");
  }
  return status;
}

}  // namespace

void RegisterVerifyCommand(CLI::App& app) {
  auto options = std::make_shared<VerifyOptions>();
  CLI::App* verify = app.add_subcommand(
      "verify",
      "Re-simulate every episode of a cell, or of every cell under a folder (a sweep), from its saved\n"
      "actions (DIR/actions: served cells, expert cells at --expert-hz 20) with the settings its cell.json\n"
      "records, and compare each record with episodes.jsonl field by field and the robot file and\n"
      "perturbation levels with the cell's identity. Writes nothing under DIR. Exit status 0: every cell\n"
      "verifies; 1: a record or a config differs; 2: a cell cannot be verified (none found, no actions,\n"
      "an unreadable file).");
  verify
      ->add_option("DIR", options->dir,
                   "A cell's folder, a folder holding cells at any depth, or a submission (a folder with\n"
                   "submission.json, whose card is checked and whose results folder is verified)")
      ->required();
  AddConfigDirOption(*verify, options->config_dir);
  verify->add_option("--threads", options->threads, "Worker threads (0 = all cores; results do not depend on it)")
      ->check(IntegerIn(0, 1024))
      ->capture_default_str();
  verify->add_option("--json", options->json_out,
                     "Also write the report as JSON to FILE (outside DIR): every cell's outcome and differences");
  verify->add_flag("--skip-unverifiable", options->skip_unverifiable,
                   "Count and list the cells without actions (built-in policies other than the expert at\n"
                   "--expert-hz 20) instead of exiting 2");
  verify->add_flag("--quiet", options->quiet, "No progress line (episodes re-simulated, rate, ETA)");
  // The exit status is the command's answer (1: a difference, 2: a cell that cannot be verified),
  // so a usage error or any other error exits 2 too, never 1: a CI gate must not read it as a
  // difference.
  verify->preparse_callback([](std::size_t) { SetUsageErrorStatus(kCannotVerifyStatus); });
  verify->callback([options] {
    int status = kCannotVerifyStatus;
    try {
      const int threads = options->threads > 0 ? options->threads : tbb::info::default_concurrency();
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
      status = Verify(*options);
    } catch (const std::exception& error) {
      throw ExitStatus(kCannotVerifyStatus, error.what());
    }
    if (status != 0) throw ExitStatus(status, "");
  });
}

}  // namespace tavis::tools

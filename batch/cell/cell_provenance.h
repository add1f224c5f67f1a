// A cell's provenance, summary.json's `provenance` section: the program (version, full git
// revision), the sha256 of every config file the cell read (the robot file, a served policy's key
// file, each perturbation axis's file), the policy's identity (its label and name; a served
// policy's servers and each server's metadata frame as it arrived, bounded, with any checkpoint
// hash it declares and any task and robot its policy was trained for), the machine and the time
// split. Nothing here is a record: the machine and the times differ from run to run, so resumes,
// merges, `tavis verify` and the record comparisons of the tests never compare this section
// (docs/verifying.md).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/evaluation_cell.h"
#include "batch/output/run_provenance.h"
#include "batch/remote/msgpack_value.h"

namespace tavis::batch::cell {

// A metadata frame over this many bytes of JSON is recorded by its size, hash and first keys, not
// whole: a server's frame is untrusted input, and summary.json must stay readable.
inline constexpr std::size_t kMaxRecordedMetadataBytes = 64 * 1024;

// The files the cell's settings read, by role: "robot", "observation_keys" (a served policy's key
// file; none for the built-in preset), "perturbations/AXIS" per chosen level.
std::vector<output::ConfigFile> CellConfigFiles(const EvaluationCellConfig& config);

// One server's metadata frame as recorded: the frame as JSON (remote::ToJson) when it is at most
// kMaxRecordedMetadataBytes, else {"omitted": why, "json_bytes", "sha256" of that JSON, "keys": its
// first 32 keys}.
nlohmann::json RecordedMetadataFrame(const remote::Value& frame);

// The checkpoint hash a frame declares: its "checkpoint_sha256" (or "checkpoint": {"sha256"}),
// when it is 64 hex digits (with or without "sha256:"), as "sha256:<hex>"; "" otherwise.
std::string DeclaredCheckpointSha256(const remote::Value& frame);

// The task and robot a frame's observation_contract says the policy was trained for, as
// {"task", "robot"} (each only when declared); null when it declares neither or is malformed.
nlohmann::json DeclaredTrainedFor(const remote::Value& frame);

// What the run was: the cell's label (a sweep's policy label; empty: its policy's name) and the
// threads it ran on.
struct ProvenanceRun {
  std::string label;
  int threads = 0;
};

// summary.json's `provenance`: {"program", "config_files", "policy", "machine", "time"}. "time":
// the cell's wall_s, and with a served policy policy_wait_s (the time spent waiting for replies)
// and simulation_s (the rest); "episodes", the episodes' time split aggregated
// (EpisodeTimesSummaryJson); with --profile, every stage's seconds (stages_s). A config file no
// longer readable is recorded as {"file", "error"}, never a failure of the finished cell.
nlohmann::json CellProvenanceJson(const CellResult& result, const ProvenanceRun& run);

}  // namespace tavis::batch::cell

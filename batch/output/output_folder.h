// The folders tavis writes results into (an eval cell, a demos dataset, a sweep, a merged sweep):
// which of them are its own, a lock so that only one process writes each, and replacing one
// (--overwrite) without losing the old result when the new run fails before it has started.
//
// A folder is tavis's own when it holds a marker (DIR/.tavis_output, naming the kind) or, for
// folders written before the marker existed, the kind's signature file (cell.json, manifest.json,
// tavis_demos.json or INCOMPLETE), AND nothing but the files and folders tavis writes for that
// kind, at every depth (a cell's videos/episode_<i>.mp4, a dataset's data/chunk-*/file-*.parquet).
// Anything else in it (a user's file, a symbolic link) makes it foreign: never replaced, never
// written into.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tavis::batch::output {

enum class OutputKind { kEvalCell, kDataset, kSweep };

// "evaluation cell", "dataset", "sweep".
const char* ToString(OutputKind kind);

// The marker and lock files tavis keeps in each of its output folders.
inline constexpr const char* kOutputMarkerFile = ".tavis_output";
inline constexpr const char* kOutputLockFile = ".tavis_lock";

// Refuses a path no command may write results into: the empty string, a plain file (or anything
// not a folder), the working directory or any folder above it (".", "..", "/"), or the home
// folder. Throws std::invalid_argument naming `option` (e.g. "--out") and the path.
void RequireUsableOutputPath(const std::filesystem::path& out, const std::string& option = "--out");

// True when DIR is absent, or a folder holding nothing but tavis's marker and lock files.
bool HoldsNoResults(const std::filesystem::path& dir);

// The entries in DIR, at any depth, that tavis does not write for `kind`, as paths inside DIR
// (a folder's with a trailing '/', and nothing listed inside it), sorted; empty when DIR holds
// only tavis's files of that kind. A symbolic link is always foreign.
std::vector<std::string> ForeignEntries(const std::filesystem::path& dir, OutputKind kind);

// True when DIR is a folder tavis wrote as `kind` (marker or signature file) and holds nothing else.
bool IsOwnOutput(const std::filesystem::path& dir, OutputKind kind);

// Throws std::invalid_argument unless DIR holds no results or is tavis's own output of `kind`;
// the message names what is in the way (at most a few entries) and `what_to_do`, whose settings
// may be marked by SettingKey (the error is then a SettingsAdvice naming them).
void RequireEmptyOrOwn(const std::filesystem::path& dir, OutputKind kind, const std::string& what_to_do);

// Writes DIR/.tavis_output ({"kind": ..., "program_version": ...}).
void WriteOutputMarker(const std::filesystem::path& dir, OutputKind kind);

// An exclusive advisory lock (flock) on DIR/.tavis_lock, held while this object lives and
// released on any exit of the process, a crash or a kill included (the kernel drops it), so a
// lock left by a dead process is simply taken over. The file records the holder (command, host,
// pid, since when), which a refused writer names.
class OutputLock {
 public:
  OutputLock() = default;
  // DIR must exist. Throws std::invalid_argument naming DIR and the holder when another process
  // holds it, std::runtime_error when the lock file cannot be created.
  OutputLock(const std::filesystem::path& dir, const std::string& command);
  ~OutputLock();
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  bool held() const { return fd_ >= 0; }
  void Release();

 private:
  int fd_ = -1;
};

// Creates DIR (and its parents) if absent, then locks it; a staging copy beside it that an
// interrupted --overwrite left (RemoveStaleStagingCopies) is removed, and said so on stderr.
OutputLock CreateAndLockOutput(const std::filesystem::path& dir, const std::string& command);

// Removes the ".NAME.tavis-new-PID" folders beside DIR whose process is gone (no process PID
// here, and their lock is free): what a killed --overwrite was building, never a result. Returns
// them. A ".NAME.tavis-old-PID" is kept: it may be the only copy of a result whose swap failed.
std::vector<std::filesystem::path> RemoveStaleStagingCopies(const std::filesystem::path& dir);

// Throws std::invalid_argument naming PATH and where it points when it is a symbolic link: a
// file tavis writes or appends to in its folder must not send its bytes elsewhere.
void RefuseLink(const std::filesystem::path& path);

// DIR as a folder of tavis's own inside an output (a cell's actions/ or videos/): created when
// absent (with its parents), refused when it is a symbolic link or not a folder.
void MakeOwnFolder(const std::filesystem::path& dir);

// True when INNER is OUTER or inside it (both resolved as far as they exist).
bool IsSameOrInside(const std::filesystem::path& inner, const std::filesystem::path& outer);

// Where this process's OutputReplacement of DIR builds the new result: ".NAME.tavis-new-PID" beside it.
std::filesystem::path StagingFolderOf(const std::filesystem::path& dir);

// Replaces a folder tavis wrote (--overwrite) by building the new result beside it: staging() is
// a fresh, locked folder next to DIR (".NAME.tavis-new-PID"); SwapIn() moves the old folder aside,
// the new one to DIR and only then removes the old one. Until SwapIn() the old result is
// untouched; destroyed without SwapIn(), the staging folder is removed. The caller holds DIR's lock.
class OutputReplacement {
 public:
  // DIR must exist and be tavis's own output of `kind` (RequireEmptyOrOwn).
  OutputReplacement(const std::filesystem::path& dir, const std::string& command);
  ~OutputReplacement();
  OutputReplacement(const OutputReplacement&) = delete;
  OutputReplacement& operator=(const OutputReplacement&) = delete;

  const std::filesystem::path& staging() const { return staging_; }
  bool swapped() const { return swapped_; }
  // Throws std::runtime_error when a rename fails (the old result is then still in DIR or beside
  // it as ".NAME.tavis-old-PID", named in the message).
  void SwapIn();

 private:
  std::filesystem::path dir_;
  std::filesystem::path staging_;
  std::filesystem::path old_;
  OutputLock staging_lock_;
  bool swapped_ = false;
};

}  // namespace tavis::batch::output

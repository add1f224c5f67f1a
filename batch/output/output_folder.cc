#include "batch/output/output_folder.h"

#include <fcntl.h>
#include <fnmatch.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <system_error>

#include <nlohmann/json.hpp>

#include "batch/output/atomic_file.h"
#include "batch/output/program_version.h"
#include "batch/output/setting_error.h"
#include "batch/output/utc_time.h"
#include "kinematics/enum_names.h"

namespace tavis::batch::output {
namespace {

namespace fs = std::filesystem;

// What tavis writes in each kind of folder, at every depth, as fnmatch patterns of the path
// inside it (a folder's with a trailing '/'). A name's ".partial" is an atomic write cut short (a
// file, or a video's frame folder being filled), matched as the name it was to become.
const std::vector<std::string>& OwnPaths(OutputKind kind) {
  // An evaluation cell's files, under `prefix` (a sweep's cells/NAME/).
  const auto cell_paths = [](const std::string& prefix) {
    return std::vector<std::string>{prefix + "cell.json",
                                    prefix + "episodes.jsonl",
                                    prefix + "episode_times.jsonl",
                                    prefix + "summary.json",
                                    prefix + "profile.json",
                                    prefix + "actions/",
                                    prefix + "actions/episode_*.csv",
                                    prefix + "actions/episode_*.csv.gz",
                                    prefix + "videos/",
                                    prefix + "videos/episode_*.mp4",
                                    prefix + "videos/episode_*/",
                                    prefix + "videos/episode_*/frame_*.png"};
  };
  static const std::vector<std::string> cell = cell_paths("");
  static const std::vector<std::string> dataset = {
      "tavis_demos.json", "tavis_rollouts.jsonl", "INCOMPLETE",
      // LeRobot v3.0 and v2.1
      "meta/", "meta/info.json", "meta/stats.json", "meta/tasks.parquet", "meta/tasks.jsonl", "meta/episodes.jsonl",
      "meta/episodes_stats.jsonl", "meta/episodes/", "meta/episodes/chunk-*/", "meta/episodes/chunk-*/file-*.parquet",
      "data/", "data/chunk-*/", "data/chunk-*/file-*.parquet", "data/chunk-*/episode_*.parquet", "videos/", "videos/*/",
      "videos/*/chunk-*/", "videos/*/chunk-*/file-*.mp4", "videos/chunk-*/*/episode_*.mp4",
      // the episodes recorded so far (batch/dataset/episode_spool.h)
      ".tavis_spool/", ".tavis_spool/episode_*/", ".tavis_spool/episode_*/data.parquet",
      ".tavis_spool/episode_*/*.packets", ".tavis_spool/episode_*/episode.json"};
  static const std::vector<std::string> sweep = [&cell_paths] {
    std::vector<std::string> paths = {"manifest.json",       "summary.json",           "report.html",  "tables/",
                                      "tables/*.md",         "tables/*.csv",           "tables/*.tex", "figures/",
                                      "figures/*.svg",       "figures/*.png",          "cells/",       "cells/*/",
                                      "cells/*/policy.json", "cells/*/sequential.json"};
    for (const std::string& path : cell_paths("cells/*/")) paths.push_back(path);
    return paths;
  }();
  switch (kind) {
    case OutputKind::kEvalCell: return cell;
    case OutputKind::kDataset: return dataset;
    case OutputKind::kSweep: return sweep;
  }
  return cell;
}

// The files that say "tavis wrote this folder as KIND" in folders written before the marker.
std::vector<std::string> SignatureFiles(OutputKind kind) {
  switch (kind) {
    case OutputKind::kEvalCell: return {"cell.json"};
    case OutputKind::kDataset: return {"tavis_demos.json", "INCOMPLETE"};
    case OutputKind::kSweep: return {"manifest.json"};
  }
  return {};
}

bool IsBookkeeping(const std::string& name) { return name == kOutputMarkerFile || name == kOutputLockFile; }

bool EndsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// "videos/episode_3.partial/frame_00000.png" as "videos/episode_3/frame_00000.png": what an
// interrupted write would have become.
std::string WithoutPartial(const fs::path& relative) {
  std::string text;
  for (const fs::path& part : relative) {
    std::string name = part.string();
    if (EndsWith(name, ".partial")) name.resize(name.size() - std::strlen(".partial"));
    text += (text.empty() ? "" : "/") + name;
  }
  return text;
}

// True when tavis writes `relative` (a folder when `folder`) in an output of `kind`. Its marker
// and lock are kept in every folder it writes (a sweep's cells too).
bool IsOwnPath(const fs::path& relative, bool folder, OutputKind kind) {
  if (!folder && IsBookkeeping(relative.filename().string())) return true;
  const std::string path = WithoutPartial(relative) + (folder ? "/" : "");
  for (const std::string& pattern : OwnPaths(kind)) {
    if (fnmatch(pattern.c_str(), path.c_str(), FNM_PATHNAME | FNM_PERIOD) == 0) return true;
  }
  return false;
}

std::string MarkerKind(const fs::path& dir) {
  std::ifstream in(dir / kOutputMarkerFile);
  if (!in) return "";
  try {
    return nlohmann::json::parse(in).value("kind", "");
  } catch (const nlohmann::json::exception&) {
    return "";
  }
}

std::string HolderText(const std::string& command) {
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  return "tavis " + command + " (pid " + std::to_string(getpid()) + " on " + host + ", since " + UtcNow() + ")";
}

std::string ReadHolder(int fd) {
  std::string text(512, '\0');
  const ssize_t got = pread(fd, text.data(), text.size(), 0);
  text.resize(got > 0 ? static_cast<std::size_t>(got) : 0);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
  return text.empty() ? "another process" : text;
}

// "/a/b/" as "/a/b", so that paths compare by their folders.
fs::path WithoutTrailingSeparator(fs::path path) {
  while (path.has_relative_path() && path.filename().empty()) path = path.parent_path();
  return path;
}

// Absolute, links and dot-dots resolved, as far as the path exists.
fs::path Resolved(const fs::path& path) {
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(path), error);
  return WithoutTrailingSeparator(error ? fs::absolute(path).lexically_normal() : resolved);
}

// The same file: the lock taken is on the file the path names now, not one removed meanwhile.
bool SameFile(int fd, const fs::path& path) {
  struct stat by_fd {
  }, by_path{};
  if (fstat(fd, &by_fd) != 0 || stat(path.c_str(), &by_path) != 0) return false;
  return by_fd.st_dev == by_path.st_dev && by_fd.st_ino == by_path.st_ino;
}

}  // namespace

const char* ToString(OutputKind kind) {
  static constexpr kinematics::EnumName<OutputKind> kNames[] = {
      {OutputKind::kEvalCell, "evaluation cell"}, {OutputKind::kDataset, "dataset"}, {OutputKind::kSweep, "sweep"}};
  return kinematics::NameOf(kNames, kind, "output");
}

void RequireUsableOutputPath(const fs::path& out, const std::string& option) {
  if (out.empty()) throw std::invalid_argument(option + " must name a folder, got an empty string");
  std::error_code error;
  if (fs::exists(out, error) && !fs::is_directory(out, error)) {
    throw std::invalid_argument(option + " " + out.string() +
                                " is a file, not a folder: tavis writes its results into a folder");
  }
  const fs::path target = Resolved(out);
  const fs::path cwd = Resolved(fs::current_path());
  // The working directory and every folder above it hold what the user works in.
  for (fs::path above = cwd;; above = above.parent_path()) {
    if (target == above) {
      throw std::invalid_argument(option + " " + out.string() + " is the working directory or a folder above it (" +
                                  target.string() + "): give a folder of its own for the results");
    }
    if (above == above.parent_path()) break;
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0' && target == Resolved(home)) {
    throw std::invalid_argument(option + " " + out.string() +
                                " is the home folder: give a folder of its own for the results");
  }
}

bool HoldsNoResults(const fs::path& dir) {
  std::error_code error;
  if (!fs::exists(dir, error)) return true;
  if (!fs::is_directory(dir, error)) return false;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    if (!IsBookkeeping(entry.path().filename().string())) return false;
  }
  return true;
}

std::vector<std::string> ForeignEntries(const fs::path& dir, OutputKind kind) {
  std::vector<std::string> foreign;
  std::error_code error;
  if (!fs::is_directory(dir, error)) return foreign;
  // Links are never followed (nor written by tavis): one is foreign wherever it points.
  fs::recursive_directory_iterator entry(dir, fs::directory_options::none, error), end;
  for (; !error && entry != end; entry.increment(error)) {
    const fs::path relative = entry->path().lexically_relative(dir);
    const bool link = entry->is_symlink(error);
    const bool folder = !link && entry->is_directory(error);
    if (!link && IsOwnPath(relative, folder, kind)) continue;
    foreign.push_back(relative.string() + (folder ? "/" : ""));
    if (folder) entry.disable_recursion_pending();  // one name says what is in the way
  }
  // A folder that cannot be read through cannot be vouched for.
  if (error) foreign.push_back("(unreadable: " + error.message() + ")");
  std::sort(foreign.begin(), foreign.end());
  return foreign;
}

bool IsOwnOutput(const fs::path& dir, OutputKind kind) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) return false;
  bool signed_as_kind = MarkerKind(dir) == ToString(kind);
  for (const std::string& file : SignatureFiles(kind)) signed_as_kind = signed_as_kind || fs::exists(dir / file, error);
  return signed_as_kind && ForeignEntries(dir, kind).empty();
}

void RequireEmptyOrOwn(const fs::path& dir, OutputKind kind, const std::string& what_to_do) {
  if (HoldsNoResults(dir) || IsOwnOutput(dir, kind)) return;
  std::vector<std::string> in_the_way = ForeignEntries(dir, kind);
  std::string names;
  if (in_the_way.empty()) {
    names = "no tavis " + std::string(ToString(kind)) + " (no " + SignatureFiles(kind).front() + ")";
  } else {
    for (std::size_t i = 0; i < in_the_way.size() && i < 5; ++i) names += (i == 0 ? "" : ", ") + in_the_way[i];
    if (in_the_way.size() > 5) names += " and " + std::to_string(in_the_way.size() - 5) + " more";
    names = "files that are not a tavis " + std::string(ToString(kind)) + "'s: " + names;
  }
  // `what_to_do` may name settings (SettingKey), which a command names by flag.
  throw SettingsAdvice<std::invalid_argument>(dir.string() + " holds " + names + "; " + what_to_do);
}

void WriteOutputMarker(const fs::path& dir, OutputKind kind) {
  const nlohmann::json marker = {{"kind", ToString(kind)}, {"program_version", ProgramVersion()}};
  WriteFileAtomically(dir / kOutputMarkerFile, marker.dump() + "\n");
}

void RefuseLink(const fs::path& path) {
  std::error_code error;
  if (!fs::is_symlink(fs::symlink_status(path, error))) return;
  throw std::invalid_argument(path.string() + " is a symbolic link (to " + fs::read_symlink(path, error).string() +
                              "); tavis writes its own files and follows no link in its folders: remove the link");
}

void MakeOwnFolder(const fs::path& dir) {
  RefuseLink(dir);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error("cannot create " + dir.string() + ": " + error.message());
  if (!fs::is_directory(fs::symlink_status(dir, error)))
    throw std::invalid_argument(dir.string() + " is not a folder: tavis writes its files into a folder there");
}

bool IsSameOrInside(const fs::path& inner, const fs::path& outer) {
  const fs::path resolved_inner = Resolved(inner);
  const fs::path resolved_outer = Resolved(outer);
  for (fs::path above = resolved_inner;; above = above.parent_path()) {
    if (above == resolved_outer) return true;
    if (above == above.parent_path()) return false;
  }
}

OutputLock::OutputLock(const fs::path& dir, const std::string& command) {
  const fs::path path = dir / kOutputLockFile;
  // The file the lock is taken on may be removed by its holder meanwhile (a replaced or failed
  // output): then the lock is taken again on the file the path names now.
  for (int attempt = 0; attempt < 100; ++attempt) {
    // Not through a link: the holder's note would truncate and fill the file it points to.
    const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) {
      const int reason = errno;
      if (reason == ELOOP) RefuseLink(path);
      throw std::runtime_error("cannot create the lock file " + path.string() + ": " + std::strerror(reason));
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int reason = errno;
      const std::string holder = ReadHolder(fd);
      close(fd);
      if (reason == EWOULDBLOCK) {
        throw std::invalid_argument(
            dir.string() + " is being written by " + holder +
            "; two writers of one folder would mix their results: wait for it to end, or stop it");
      }
      throw std::runtime_error("cannot lock " + path.string() + ": " + std::strerror(reason));
    }
    if (!SameFile(fd, path)) {
      close(fd);
      if (!fs::exists(dir))
        throw std::invalid_argument(dir.string() + " was removed by another process while being locked");
      continue;
    }
    const std::string holder = HolderText(command) + "\n";
    if (ftruncate(fd, 0) != 0 || pwrite(fd, holder.data(), holder.size(), 0) != static_cast<ssize_t>(holder.size())) {
      // The lock holds without the note; a refused writer then names "another process".
    }
    fd_ = fd;
    return;
  }
  throw std::runtime_error("cannot lock " + path.string() + ": it is being replaced over and over");
}

OutputLock::~OutputLock() { Release(); }

OutputLock::OutputLock(OutputLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    Release();
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

void OutputLock::Release() {
  // The holder's note goes first (a finished run leaves an empty lock file, the same in every
  // run); closing the only descriptor then drops the flock.
  if (fd_ >= 0 && ftruncate(fd_, 0) != 0) {
    // An unwritable note changes nothing: the lock itself goes with the descriptor.
  }
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
}

std::vector<fs::path> RemoveStaleStagingCopies(const fs::path& dir) {
  std::vector<fs::path> removed;
  const fs::path resolved = Resolved(dir);
  const std::string prefix = "." + resolved.filename().string() + ".tavis-new-";
  std::error_code error;
  fs::directory_iterator entry(resolved.parent_path(), error), end;
  for (; !error && entry != end; entry.increment(error)) {
    const std::string name = entry->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string pid_text = name.substr(prefix.size());
    if (pid_text.find_first_not_of("0123456789") != std::string::npos || pid_text.size() > 9) continue;
    std::error_code ignored;
    if (!fs::is_directory(fs::symlink_status(entry->path(), ignored))) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(pid_text));
    // Its maker is gone: no process of that number, and nobody holds the copy's lock.
    if (pid == getpid() || kill(pid, 0) == 0 || errno != ESRCH) continue;
    const int lock = open((entry->path() / kOutputLockFile).c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    const bool held = lock >= 0 && flock(lock, LOCK_EX | LOCK_NB) != 0;
    if (lock >= 0) close(lock);
    if (held) continue;
    removed.push_back(entry->path());
  }
  for (const fs::path& stale : removed) fs::remove_all(stale, error);
  return removed;
}

OutputLock CreateAndLockOutput(const fs::path& dir, const std::string& command) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error("cannot create " + dir.string() + ": " + error.message());
  OutputLock lock(dir, command);
  // Whoever replaced DIR held this lock: a copy it left is stale once it is ours.
  for (const fs::path& stale : RemoveStaleStagingCopies(dir)) {
    std::cerr << "note: removed " << stale.string() << ", the unfinished copy an interrupted --overwrite of "
              << dir.string() << " left\n";
  }
  return lock;
}

fs::path StagingFolderOf(const fs::path& dir) {
  const fs::path resolved = Resolved(dir);
  return resolved.parent_path() / ("." + resolved.filename().string() + ".tavis-new-" + std::to_string(getpid()));
}

OutputReplacement::OutputReplacement(const fs::path& dir, const std::string& command) : dir_(Resolved(dir)) {
  const fs::path name = dir_.filename();
  const fs::path parent = dir_.parent_path();
  staging_ = StagingFolderOf(dir_);
  old_ = parent / ("." + name.string() + ".tavis-old-" + std::to_string(getpid()));
  std::error_code error;
  fs::remove_all(staging_, error);  // one left by an earlier run of this pid number: never a result
  fs::create_directory(staging_, error);
  if (error)
    throw std::runtime_error("cannot create " + staging_.string() + " beside " + dir_.string() + ": " +
                             error.message());
  staging_lock_ = OutputLock(staging_, command);
}

OutputReplacement::~OutputReplacement() {
  if (swapped_) return;
  staging_lock_.Release();
  std::error_code ignored;
  fs::remove_all(staging_, ignored);
}

void OutputReplacement::SwapIn() {
  if (swapped_) return;
  const fs::path& old = old_;
  std::error_code error;
  fs::rename(dir_, old, error);
  if (error)
    throw std::runtime_error("cannot move " + dir_.string() + " aside to " + old.string() + ": " + error.message());
  fs::rename(staging_, dir_, error);
  if (error) {
    std::error_code ignored;
    fs::rename(old, dir_, ignored);
    throw std::runtime_error("cannot move the new result " + staging_.string() + " to " + dir_.string() + ": " +
                             error.message() + (ignored ? "; the old result is in " + old.string() : ""));
  }
  swapped_ = true;
  fs::remove_all(old, error);
  if (error) throw std::runtime_error("the old result " + old.string() + " could not be removed: " + error.message());
}

}  // namespace tavis::batch::output

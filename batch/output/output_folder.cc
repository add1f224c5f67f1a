#include "batch/output/output_folder.h"

#include <fcntl.h>
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
#include <set>
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

// What tavis writes at the top of each kind of folder. FILE.partial is an atomic write cut short.
const std::set<std::string>& OwnEntries(OutputKind kind) {
  static const std::set<std::string> cell = {"cell.json",    "episodes.jsonl", "summary.json",
                                             "profile.json", "actions",        "videos"};
  static const std::set<std::string> dataset = {"meta",         "data",       "videos",
                                                ".tavis_spool", "INCOMPLETE", "tavis_demos.json"};
  static const std::set<std::string> sweep = {"manifest.json", "cells",   "summary.json",
                                              "tables",        "figures", "report.html"};
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
  const std::set<std::string>& own = OwnEntries(kind);
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (IsBookkeeping(name) || own.count(name) > 0 || EndsWith(name, ".partial")) continue;
    foreign.push_back(name);
  }
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

OutputLock::OutputLock(const fs::path& dir, const std::string& command) {
  const fs::path path = dir / kOutputLockFile;
  // The file the lock is taken on may be removed by its holder meanwhile (a replaced or failed
  // output): then the lock is taken again on the file the path names now.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error("cannot create the lock file " + path.string() + ": " + std::strerror(errno));
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

OutputLock CreateAndLockOutput(const fs::path& dir, const std::string& command) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error("cannot create " + dir.string() + ": " + error.message());
  return OutputLock(dir, command);
}

OutputReplacement::OutputReplacement(const fs::path& dir, const std::string& command) : dir_(Resolved(dir)) {
  const fs::path name = dir_.filename();
  const fs::path parent = dir_.parent_path();
  staging_ = parent / ("." + name.string() + ".tavis-new-" + std::to_string(getpid()));
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

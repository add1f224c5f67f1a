#include "batch/output/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace tavis::batch::output {
namespace {

std::string PartialOf(const std::filesystem::path& path) { return path.string() + ".partial"; }

std::runtime_error WriteError(const std::string& file, int reason) {
  return std::runtime_error("cannot write " + file + ": " + std::strerror(reason));
}

}  // namespace

std::filesystem::path FreshPartialPath(const std::filesystem::path& path) {
  const std::string temporary = PartialOf(path);
  if (::unlink(temporary.c_str()) != 0 && errno != ENOENT) throw WriteError(temporary, errno);
  return temporary;
}

void RenamePartialIntoPlace(const std::filesystem::path& path) {
  const std::string temporary = PartialOf(path);
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    throw std::runtime_error("cannot rename " + temporary + " to " + path.string() + ": " + std::strerror(errno));
  }
}

void WriteFileAtomically(const std::filesystem::path& path, const std::string& text) {
  const std::string temporary = FreshPartialPath(path).string();
  // O_EXCL: a file (or link) that appeared at the name meanwhile is refused, not written through.
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw WriteError(temporary, errno);
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t wrote = ::write(fd, text.data() + done, text.size() - done);
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) {
      const int reason = wrote < 0 ? errno : ENOSPC;
      ::close(fd);
      ::unlink(temporary.c_str());
      throw WriteError(temporary, reason);
    }
    done += static_cast<std::size_t>(wrote);
  }
  if (::close(fd) != 0) {
    const int reason = errno;
    ::unlink(temporary.c_str());
    throw WriteError(temporary, reason);
  }
  RenamePartialIntoPlace(path);
}

}  // namespace tavis::batch::output

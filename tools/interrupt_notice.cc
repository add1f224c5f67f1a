#include "tools/interrupt_notice.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <mutex>
#include <thread>

namespace tavis::tools {
namespace {

struct InterruptState {
  std::mutex mutex;
  std::function<std::string()> describe;
  std::vector<std::string> argv;
};

InterruptState& State() {
  static InterruptState state;
  return state;
}

sigset_t InterruptSignals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  return signals;
}

[[noreturn]] void Watch() {
  const sigset_t signals = InterruptSignals();
  int received = 0;
  while (sigwait(&signals, &received) != 0) {
  }
  std::function<std::string()> describe;
  {
    const std::lock_guard<std::mutex> lock(State().mutex);
    describe = State().describe;
  }
  std::string line;
  try {
    if (describe) line = describe();
  } catch (const std::exception& error) {
    line = std::string("interrupted (what was kept could not be read: ") + error.what() + ")";
  }
  if (!line.empty()) {
    line = "\n" + line + "\n";  // after a progress line rewritten in place
    if (::write(STDERR_FILENO, line.data(), line.size()) < 0) {
      // Nothing more to do: the program ends either way.
    }
  }
  // Ended by the signal itself: the default action, delivered to this thread, unblocked here.
  signal(received, SIG_DFL);
  sigset_t only;
  sigemptyset(&only);
  sigaddset(&only, received);
  pthread_sigmask(SIG_UNBLOCK, &only, nullptr);
  raise(received);
  _exit(128 + received);  // not reached
}

}  // namespace

void WatchForInterrupts(int argc, char** argv) {
  State().argv.assign(argv, argv + argc);
  const sigset_t signals = InterruptSignals();
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::thread(Watch).detach();
}

void SetInterruptNotice(std::function<std::string()> describe) {
  const std::lock_guard<std::mutex> lock(State().mutex);
  State().describe = std::move(describe);
}

std::string ShellWord(const std::string& word) {
  const bool plain = !word.empty() && std::all_of(word.begin(), word.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || std::string("-_./=:,+@%").find(c) != std::string::npos;
  });
  if (plain) return word;
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string CommandLineWith(const std::vector<std::string>& drop_flags, const std::vector<std::string>& drop_options,
                            const std::string& add) {
  const std::vector<std::string>& argv = State().argv;
  const auto listed = [](const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  std::string line;
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& word = argv[i];
    const std::string name = word.substr(0, word.find('='));
    if (i > 0 && listed(drop_flags, word)) continue;
    if (i > 0 && listed(drop_options, name)) {
      if (name == word) ++i;  // "--out DIR": its value goes too
      continue;
    }
    line += (line.empty() ? "" : " ") + ShellWord(word);
  }
  return add.empty() ? line : line + " " + add;
}

std::string KeptLine(int64_t episodes, const std::filesystem::path& folder, const std::string& what,
                     const std::string& command) {
  return "interrupted: " + std::to_string(episodes) + (episodes == 1 ? " episode" : " episodes") + " kept in " +
         folder.string() + "; to finish " + what + ": " + command;
}

int64_t CompleteLines(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return static_cast<int64_t>(std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n'));
}

}  // namespace tavis::tools

#include "scanbus/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace scanbus {

std::string own_executable() {
  char self[4096] = {};
  if (readlink("/proc/self/exe", self, sizeof(self) - 1) < 0) throw std::runtime_error("cannot find own executable");
  return self;
}

namespace {

// This process's environment with `overrides` set over it, as "NAME=value" lines.
std::vector<std::string> environment_with(const std::map<std::string, std::string>& overrides) {
  std::vector<std::string> lines;
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string line = *entry;
    if (overrides.count(line.substr(0, line.find('='))) == 0) lines.push_back(line);
  }
  for (const auto& [name, value] : overrides) lines.push_back(name + "=" + value);
  return lines;
}

}  // namespace

ChildProcess::ChildProcess(const std::string& executable, const std::vector<std::string>& arguments,
                           const std::string& log_path, const std::map<std::string, std::string>& environment)
    : log_path_(log_path) {
  name_ = executable.substr(executable.rfind('/') + 1);  // e.g. "scanbus run scanner_io"
  for (size_t i = 0; i < arguments.size() && i < 2; ++i) name_ += " " + arguments[i];
  std::string program = executable;
  std::vector<std::string> words = arguments;
  std::vector<char*> argv = {program.data()};
  for (auto& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  std::vector<std::string> variables = environment_with(environment);
  std::vector<char*> envp;
  for (auto& variable : variables) envp.push_back(variable.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // The CLI blocks SIGINT/SIGTERM for its own stop handling; children start with them open.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
  const int error = posix_spawn(&pid_, program.c_str(), &actions, &attributes, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (error != 0) throw std::runtime_error("cannot start " + name_ + ": " + std::strerror(error));
}

ChildProcess::~ChildProcess() {
  if (pid_ <= 0) return;
  kill(pid_, SIGTERM);
  // Services stop within a second of SIGTERM; one that does not must not hang its parent.
  for (int waited_ms = 0; waited_ms < 10000; waited_ms += 20) {
    if (exited()) return;
    usleep(20000);
  }
  std::fprintf(stderr, "%s did not stop within 10 s of SIGTERM: killed (see %s)\n", name_.c_str(), log_path_.c_str());
  kill(pid_, SIGKILL);
  int status = 0;
  waitpid(pid_, &status, 0);
}

void ChildProcess::expect_running() {
  if (auto status = exited())
    throw std::runtime_error(name_ + " exited early with status " + std::to_string(*status) + " (see " + log_path_ +
                             ")");
}

std::optional<int> ChildProcess::exited() {
  int status = 0;
  const pid_t waited = pid_ > 0 ? waitpid(pid_, &status, WNOHANG) : 0;
  if (waited == pid_ && pid_ > 0) {
    pid_ = 0;
    exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  } else if (waited < 0 && errno == ECHILD) {
    pid_ = 0;  // reaped elsewhere: gone, its status unknown
    exit_status_ = -1;
  }
  return pid_ == 0 ? std::optional<int>(exit_status_) : std::nullopt;
}

}  // namespace scanbus

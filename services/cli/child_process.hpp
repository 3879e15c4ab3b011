// A program started by the CLI (a service, the simulator), stopped with SIGTERM when this
// object goes away. Its stdout and stderr go to a log file.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace scanbus::cli {

class ChildProcess {
 public:
  // argv[0] is run from this executable's own path (`scanbus ...`).
  ChildProcess(const std::vector<std::string>& arguments, const std::string& log_path);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // The exit status when it has ended on its own.
  std::optional<int> exited();
  const std::string& name() const { return name_; }
  const std::string& log_path() const { return log_path_; }

 private:
  std::string name_, log_path_;
  pid_t pid_ = 0;
  int exit_status_ = 0;
};

}  // namespace scanbus::cli

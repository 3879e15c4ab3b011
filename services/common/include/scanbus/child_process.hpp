// A program started as a separate process (a service, the simulator), stopped with
// SIGTERM when this object goes away. Its stdout and stderr go to a log file.
#pragma once

#include <sys/types.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace scanbus {

class ChildProcess {
 public:
  // `environment` is set in the child's environment over this process's own (this process's
  // stays as it is).
  ChildProcess(const std::string& executable, const std::vector<std::string>& arguments, const std::string& log_path,
               const std::map<std::string, std::string>& environment = {});
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // The exit status when it has ended on its own.
  std::optional<int> exited();
  // Throws std::runtime_error naming it, its status and its log when it has ended.
  void expect_running();
  const std::string& name() const { return name_; }
  const std::string& log_path() const { return log_path_; }

 private:
  std::string name_, log_path_;
  pid_t pid_ = 0;
  int exit_status_ = 0;
};

// This program's own executable (to start `scanbus run ...` from the scanbus command).
std::string own_executable();

}  // namespace scanbus

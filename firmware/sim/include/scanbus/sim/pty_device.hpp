// The simulator's end of a pseudo-terminal: the other end is a tty a serial client opens
// like a USB serial device.
#pragma once

#include <string>

namespace scanbus::sim {

class PtyDevice {
 public:
  // Opens a pty (raw, no echo); with a link path, points a symlink there at it.
  PtyDevice(const std::string& link);
  ~PtyDevice();
  PtyDevice(const PtyDevice&) = delete;
  PtyDevice& operator=(const PtyDevice&) = delete;

  const std::string& path() const { return path_; }
  // Bytes the client sent; empty when none.
  std::string read();
  // Writes what the client's buffer takes; returns the bytes written.
  size_t write(const std::string& bytes);

 private:
  int master_ = -1;
  int slave_ = -1;  // held open: output waits in the pty while no client has it open
  std::string path_, link_;
};

}  // namespace scanbus::sim

// A serial device (USB CDC, UART or pseudo-terminal) in raw mode, read as lines.
#pragma once

#include <string>
#include <vector>

namespace scanbus::scanner_io {

class SerialPort {
 public:
  static constexpr size_t kMaxLineLength = 512;  // longer runs without '\n' are garbage

  SerialPort(std::string path, int baud) : path_(std::move(path)), baud_(baud) {}
  ~SerialPort() { close(); }
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // Opens and configures the device; on failure returns false with the reason in `error`.
  bool open(std::string& error);
  void close();
  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

  // Waits up to `timeout_ms` for data and appends each complete line to `lines`. Returns
  // false when the device went away (unplugged, pty closed); the port is closed then.
  bool read_lines(std::vector<std::string>& lines, int timeout_ms);
  bool write_line(const std::string& line);
  // Lines dropped because they grew past kMaxLineLength.
  size_t overlong_lines() const { return overlong_lines_; }

 private:
  std::string path_;
  int baud_;
  int fd_ = -1;
  std::string partial_;
  bool discarding_ = false;  // inside an overlong line: skip to its end
  size_t overlong_lines_ = 0;
};

// True for the baud rates the port accepts.
bool supported_baud(int baud);

}  // namespace scanbus::scanner_io

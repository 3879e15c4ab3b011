#include "serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace scanbus::scanner_io {

namespace {

speed_t speed_of(int baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
  }
  return B0;
}

}  // namespace

bool supported_baud(int baud) { return speed_of(baud) != B0; }

bool SerialPort::open(std::string& error) {
  close();
  fd_ = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    error = path_ + ": " + std::strerror(errno);
    return false;
  }
  termios settings{};
  if (tcgetattr(fd_, &settings) != 0) {
    error = path_ + ": not a serial device: " + std::strerror(errno);
    close();
    return false;
  }
  cfmakeraw(&settings);
  settings.c_cflag |= CLOCAL | CREAD;
  cfsetispeed(&settings, speed_of(baud_));
  cfsetospeed(&settings, speed_of(baud_));
  if (tcsetattr(fd_, TCSANOW, &settings) != 0) {
    error = path_ + ": cannot configure: " + std::strerror(errno);
    close();
    return false;
  }
  partial_.clear();
  discarding_ = false;
  return true;
}

void SerialPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool SerialPort::read_lines(std::vector<std::string>& lines, int timeout_ms) {
  if (fd_ < 0) return false;
  pollfd request{fd_, POLLIN, 0};
  const int ready = poll(&request, 1, timeout_ms);
  if (ready < 0) return errno == EINTR;
  if (ready == 0) return true;
  if (!(request.revents & POLLIN) && (request.revents & (POLLHUP | POLLERR | POLLNVAL))) {
    close();
    return false;
  }
  char buffer[4096];
  const ssize_t count = ::read(fd_, buffer, sizeof(buffer));
  if (count == 0 || (count < 0 && errno != EAGAIN && errno != EINTR)) {
    close();
    return false;
  }
  for (ssize_t i = 0; i < count; ++i) {
    if (buffer[i] == '\n') {
      if (!discarding_) lines.push_back(std::move(partial_));
      partial_.clear();
      discarding_ = false;
    } else if (discarding_) {
      continue;
    } else if (partial_.size() < kMaxLineLength) {
      partial_ += buffer[i];
    } else {
      ++overlong_lines_;
      partial_.clear();
      discarding_ = true;
    }
  }
  return true;
}

bool SerialPort::write_line(const std::string& line) {
  if (fd_ < 0) return false;
  const std::string framed = line + "\n";
  size_t written = 0;
  for (int attempts = 0; written < framed.size() && attempts < 50; ++attempts) {
    const ssize_t count = ::write(fd_, framed.data() + written, framed.size() - written);
    if (count > 0) {
      written += static_cast<size_t>(count);
    } else if (count < 0 && errno != EAGAIN && errno != EINTR) {
      return false;
    } else {
      usleep(1000);
    }
  }
  return written == framed.size();
}

}  // namespace scanbus::scanner_io

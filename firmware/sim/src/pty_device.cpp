#include "scanbus/sim/pty_device.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace scanbus::sim {

PtyDevice::PtyDevice(const std::string& link) : link_(link) {
  master_ = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (master_ < 0 || grantpt(master_) != 0 || unlockpt(master_) != 0)
    throw std::runtime_error(std::string("cannot open a pseudo-terminal: ") + std::strerror(errno));
  path_ = ptsname(master_);
  slave_ = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  termios settings{};
  if (slave_ < 0 || tcgetattr(slave_, &settings) != 0) throw std::runtime_error(path_ + ": " + std::strerror(errno));
  cfmakeraw(&settings);  // no echo: the device's lines must not come back as commands
  tcsetattr(slave_, TCSANOW, &settings);
  if (!link_.empty()) {
    ::unlink(link_.c_str());
    if (::symlink(path_.c_str(), link_.c_str()) != 0)
      throw std::runtime_error(link_ + ": cannot link to " + path_ + ": " + std::strerror(errno));
  }
}

PtyDevice::~PtyDevice() {
  if (!link_.empty()) ::unlink(link_.c_str());
  if (slave_ >= 0) ::close(slave_);
  if (master_ >= 0) ::close(master_);
}

std::string PtyDevice::read() {
  char buffer[1024];
  const ssize_t count = ::read(master_, buffer, sizeof(buffer));
  return count > 0 ? std::string(buffer, static_cast<size_t>(count)) : std::string();
}

size_t PtyDevice::write(const std::string& bytes) {
  const ssize_t count = ::write(master_, bytes.data(), bytes.size());
  return count > 0 ? static_cast<size_t>(count) : 0;
}

}  // namespace scanbus::sim

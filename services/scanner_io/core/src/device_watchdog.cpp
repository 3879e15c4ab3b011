#include "scanbus/scanner_io/device_watchdog.hpp"

#include <algorithm>

namespace scanbus::scanner_io {

DeviceWatchdog::DeviceWatchdog(double timeout, double min_backoff, double max_backoff)
    : timeout_(timeout), min_backoff_(min_backoff), max_backoff_(max_backoff), backoff_(min_backoff) {}

void DeviceWatchdog::line(double now) {
  backoff_ = min_backoff_;
  if (since_) since_ = now;
}

void DeviceWatchdog::expect(bool due, double now) {
  if (!due) {
    since_.reset();
  } else if (!since_) {
    since_ = now;
  }
}

bool DeviceWatchdog::stalled(double now) const { return since_ && now - *since_ > timeout_; }

double DeviceWatchdog::reset() {
  since_.reset();  // due again once the reopened session asks the device where it stands
  const double wait = backoff_;
  backoff_ = std::min(backoff_ * 2, max_backoff_);
  return wait;
}

}  // namespace scanbus::scanner_io

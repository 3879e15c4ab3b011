// Tells a device that stopped talking from one that has nothing to say. While lines are due
// (a scan runs, a command waits for its answer), none for `timeout` s means the device
// stalled: a frozen firmware, or a USB serial bridge that keeps the port open with nothing
// behind it, which the port alone never reports. The session is then reset (closed, opened
// again, asked where it stands); a device that stays silent is reset again after a back-off
// that doubles each time, from `min_backoff` to `max_backoff`, until a line comes.
#pragma once

#include <optional>

namespace scanbus::scanner_io {

class DeviceWatchdog {
 public:
  DeviceWatchdog(double timeout, double min_backoff, double max_backoff);

  // `now` in s on a steady clock.
  void line(double now);              // the device said something
  void expect(bool due, double now);  // whether lines are due now (scanning, a command sent)
  bool stalled(double now) const;     // due, and silent for longer than allowed
  // The session was reset: the s to wait before opening it again.
  double reset();

  double silent_for(double now) const { return since_ ? now - *since_ : 0; }

 private:
  double timeout_, min_backoff_, max_backoff_;
  double backoff_;
  std::optional<double> since_;  // lines due since the last line (or since they became due)
};

}  // namespace scanbus::scanner_io

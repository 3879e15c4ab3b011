// Stamps as ROS 2 builtin_interfaces/Time (wall clock, like ROS 2's system time).
#pragma once

#include <chrono>

#include "scanbus_msgs/Time.h"

namespace scanbus {

inline builtin_interfaces::msg::Time to_stamp(double seconds) {
  builtin_interfaces::msg::Time stamp;
  const auto whole = static_cast<int32_t>(seconds);
  stamp.sec(whole);
  stamp.nanosec(static_cast<uint32_t>((seconds - whole) * 1e9));
  return stamp;
}

inline double to_seconds(const builtin_interfaces::msg::Time& stamp) { return stamp.sec() + stamp.nanosec() * 1e-9; }

inline builtin_interfaces::msg::Time now_stamp() {
  const auto since_epoch = std::chrono::system_clock::now().time_since_epoch();
  builtin_interfaces::msg::Time stamp;
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(since_epoch);
  stamp.sec(static_cast<int32_t>(seconds.count()));
  stamp.nanosec(
      static_cast<uint32_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(since_epoch - seconds).count()));
  return stamp;
}

// Seconds on the monotonic clock: for timeouts and back-offs, which a wall-clock step must not move.
inline double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace scanbus

// Stamps as ROS 2 builtin_interfaces/Time (wall clock, like ROS 2's system time).
#pragma once

#include <chrono>
#include <cstdint>

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

// Nanoseconds since the epoch on the wall clock, and a stamp to and from them (MCAP log
// times, Foxglove's receive times, rt/clock).
inline uint64_t wall_clock_ns() {
  return static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}
inline uint64_t to_nanoseconds(const builtin_interfaces::msg::Time& stamp) {
  return static_cast<uint64_t>(stamp.sec()) * 1000000000ull + stamp.nanosec();
}
inline builtin_interfaces::msg::Time stamp_of_nanoseconds(uint64_t ns) {
  builtin_interfaces::msg::Time stamp;
  stamp.sec(static_cast<int32_t>(ns / 1000000000ull));
  stamp.nanosec(static_cast<uint32_t>(ns % 1000000000ull));
  return stamp;
}

// Seconds on the monotonic clock: for timeouts and back-offs, which a wall-clock step must not move.
inline double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace scanbus

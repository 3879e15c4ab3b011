#include "scanbus/replay_pacer.hpp"

#include <algorithm>
#include <cmath>

namespace scanbus {

namespace {

// Beyond this a due time is never reached anyway; below it, converting it to the clock's
// int64 nanoseconds cannot overflow (about 9.2e9 s).
constexpr double kLatestDue = 1e9;

}  // namespace

ReplayPacer::ReplayPacer(double rate, double max_gap) : rate_(rate), max_gap_(max_gap) {}

double ReplayPacer::due_of(double stamp) const {
  if (!(rate_ > 0)) return 0;  // as fast as possible
  const double due = (stamp - *first_ - removed_) / rate_;
  return std::isnan(due) ? 0 : std::clamp(due, 0.0, kLatestDue);
}

ReplayPacer::Step ReplayPacer::next(double stamp) {
  Step step;
  const auto near = [&](double a, double b) { return std::abs(a - b) <= max_gap_; };
  if (!first_) {
    first_ = previous_ = stamp;
    return step;
  }
  if (held_) {
    if (near(stamp, *held_) && !near(stamp, *previous_)) {
      // A pause: the held message goes now, and the pace goes on from it.
      step.publish_held = true;
      removed_ += *held_ - *previous_;
      previous_ = held_;
      ++pauses_;
    } else {
      step.skip_held = true;
      ++skipped_;
    }
    held_.reset();
  }
  if (!near(stamp, *previous_)) {
    held_ = stamp;
    step.hold = true;
    return step;
  }
  previous_ = stamp;
  step.due = due_of(stamp);
  return step;
}

bool ReplayPacer::finish() {
  if (!held_) return false;
  held_.reset();
  ++skipped_;
  return true;
}

}  // namespace scanbus

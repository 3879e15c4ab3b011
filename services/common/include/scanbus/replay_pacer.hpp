// When each message of a replay is due, from its stamp: `rate` times the recorded pace.
// A stamp more than `max_gap` from the previous message's (ahead or behind) is held back
// until the next message tells what it is: alone, a broken stamp, skipped (the replay would
// otherwise wait for it, up to the overflow of the clock); followed by messages near it, a
// pause in the recording, replayed at once and the pace taken up from there.
#pragma once

#include <optional>

namespace scanbus {

class ReplayPacer {
 public:
  // rate: times the recorded pace (0: every message due at once); max_gap in s.
  ReplayPacer(double rate, double max_gap);

  struct Step {
    bool publish_held = false;  // the held message goes now, before this one
    bool skip_held = false;     // the held message's stamp was broken
    bool hold = false;          // this message waits for the next (its stamp jumps)
    double due = 0;             // s after the replay's start this message is due (unless held)
  };
  // The next message, stamped `stamp` (s, any origin).
  Step next(double stamp);
  // At the end: true when a held message is left, a broken stamp to skip.
  bool finish();

  unsigned long skipped() const { return skipped_; }  // broken stamps
  unsigned long pauses() const { return pauses_; }    // gaps over max_gap taken up

 private:
  double due_of(double stamp) const;

  double rate_, max_gap_;
  std::optional<double> first_, previous_, held_;
  double removed_ = 0;  // s of pauses taken out of the pace
  unsigned long skipped_ = 0, pauses_ = 0;
};

}  // namespace scanbus

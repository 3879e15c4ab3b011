// One client's frames waiting to be sent, bounded in bytes, so a client that reads slowly
// never holds up DDS or the other clients: over the bound it loses the oldest samples of the
// channel that just grew first (a newer cloud replaces an older one), then the oldest of any
// channel. Control messages are never dropped. Not thread-safe: its owner (a client's
// connection) locks.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scanbus/foxglove_bridge/protocol.hpp"

namespace scanbus::foxglove_bridge {

struct Frame {
  // Control: JSON that is always delivered (advertise, unadvertise, errors). Sample: a
  // channel's sample, dropped first when the client falls behind. Time, Progress: only the
  // newest queued one matters (the clock, the latest count of drops), so it replaces older ones.
  enum class Kind { Control, Sample, Time, Progress };
  Kind kind = Kind::Control;
  std::string text;  // JSON (Control, Progress)
  // A binary frame (Sample, Time): header, then payload (a sample's bytes, shared by every
  // client's frame).
  uint32_t channel_id = 0;  // Sample: the channel it belongs to
  std::vector<uint8_t> header;
  std::shared_ptr<const std::vector<uint8_t>> payload;

  static Frame control(std::string json);
  static Frame progress(std::string json);
  static Frame sample(uint32_t channel_id, uint32_t subscription_id, uint64_t receive_time_ns,
                      std::shared_ptr<const std::vector<uint8_t>> bytes);
  static Frame time(uint64_t time_ns);
  bool binary() const { return kind == Kind::Sample || kind == Kind::Time; }
  size_t size() const { return text.size() + header.size() + (payload ? payload->size() : 0); }
};

class SendQueue {
 public:
  explicit SendQueue(size_t max_bytes) : max_bytes_(max_bytes) {}

  // Queues the frame, then drops older samples while over the bound (never the new frame:
  // one sample larger than the bound is still sent, alone). False when control messages
  // alone exceed the bound: the client reads nothing while it keeps asking, and its
  // connection should be closed.
  bool push(Frame frame);
  // Control messages and samples in order; the newest Progress and Time before them.
  std::optional<Frame> pop();
  bool empty() const { return frames_.empty() && !time_ && !progress_; }
  size_t bytes() const { return bytes_; }
  uint64_t dropped() const { return dropped_; }
  const std::map<uint32_t, uint64_t>& dropped_by_channel() const { return dropped_by_channel_; }

 private:
  // The oldest sample, of `channel_id` when given, but not the newest frame.
  std::deque<Frame>::iterator oldest_sample(std::optional<uint32_t> channel_id);

  size_t max_bytes_;
  size_t bytes_ = 0;                           // every frame queued, the slots included
  size_t control_bytes_ = 0;                   // control messages in frames_
  std::deque<Frame> frames_;                   // control messages and samples
  std::optional<Frame> time_, progress_;       // the newest of each: one slot, no search
  std::map<uint32_t, size_t> samples_queued_;  // by channel, so a channel with none is not searched for
  uint64_t dropped_ = 0;
  std::map<uint32_t, uint64_t> dropped_by_channel_;
};

}  // namespace scanbus::foxglove_bridge

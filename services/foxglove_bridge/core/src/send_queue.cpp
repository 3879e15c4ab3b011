#include "scanbus/foxglove_bridge/send_queue.hpp"

namespace scanbus::foxglove_bridge {

Frame Frame::control(std::string json) {
  Frame frame;
  frame.text = std::move(json);
  return frame;
}

Frame Frame::progress(std::string json) {
  Frame frame = control(std::move(json));
  frame.kind = Kind::Progress;
  return frame;
}

Frame Frame::sample(uint32_t channel_id, uint32_t subscription_id, uint64_t receive_time_ns,
                    std::shared_ptr<const std::vector<uint8_t>> bytes) {
  Frame frame;
  frame.kind = Kind::Sample;
  frame.channel_id = channel_id;
  const auto header = message_data_header(subscription_id, receive_time_ns);
  frame.header.assign(header.begin(), header.end());
  frame.payload = std::move(bytes);
  return frame;
}

Frame Frame::time(uint64_t time_ns) {
  Frame frame;
  frame.kind = Kind::Time;
  const auto bytes = time_frame(time_ns);
  frame.header.assign(bytes.begin(), bytes.end());
  return frame;
}

bool SendQueue::push(Frame frame) {
  bytes_ += frame.size();
  if (frame.kind == Frame::Kind::Time || frame.kind == Frame::Kind::Progress) {
    std::optional<Frame>& slot = frame.kind == Frame::Kind::Time ? time_ : progress_;
    if (slot) bytes_ -= slot->size();
    slot = std::move(frame);
    return true;
  }
  const bool sample = frame.kind == Frame::Kind::Sample;
  const uint32_t channel = frame.channel_id;
  if (sample)
    ++samples_queued_[channel];
  else
    control_bytes_ += frame.size();
  frames_.push_back(std::move(frame));
  while (bytes_ > max_bytes_) {
    auto victim = sample && samples_queued_[channel] > 1 ? oldest_sample(channel) : frames_.end();
    if (victim == frames_.end()) victim = oldest_sample(std::nullopt);
    if (victim == frames_.end()) break;  // only control messages and the new frame are left
    ++dropped_;
    ++dropped_by_channel_[victim->channel_id];
    --samples_queued_[victim->channel_id];
    bytes_ -= victim->size();
    frames_.erase(victim);
  }
  return control_bytes_ <= max_bytes_;
}

std::optional<Frame> SendQueue::pop() {
  std::optional<Frame> frame;
  if (progress_) {
    frame.swap(progress_);
  } else if (time_) {
    frame.swap(time_);
  } else if (!frames_.empty()) {
    frame = std::move(frames_.front());
    frames_.pop_front();
    if (frame->kind == Frame::Kind::Sample)
      --samples_queued_[frame->channel_id];
    else
      control_bytes_ -= frame->size();
  }
  if (frame) bytes_ -= frame->size();
  return frame;
}

std::deque<Frame>::iterator SendQueue::oldest_sample(std::optional<uint32_t> channel_id) {
  const auto newest = frames_.end() - 1;
  for (auto it = frames_.begin(); it != newest; ++it)
    if (it->kind == Frame::Kind::Sample && (!channel_id || it->channel_id == *channel_id)) return it;
  return frames_.end();
}

}  // namespace scanbus::foxglove_bridge

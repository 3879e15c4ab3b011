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

void SendQueue::push(Frame frame) {
  const Frame::Kind kind = frame.kind;
  if (kind == Frame::Kind::Time || kind == Frame::Kind::Progress)
    for (auto it = frames_.begin(); it != frames_.end();) it = it->kind == kind ? erase(it) : it + 1;
  const std::optional<uint32_t> channel =
      kind == Frame::Kind::Sample ? std::optional<uint32_t>(frame.channel_id) : std::nullopt;
  bytes_ += frame.size();
  frames_.push_back(std::move(frame));
  while (bytes_ > max_bytes_) {
    auto victim = channel ? oldest_sample(channel) : frames_.end();
    if (victim == frames_.end()) victim = oldest_sample(std::nullopt);
    if (victim == frames_.end()) return;  // only frames that are not samples, and the new one, are left
    ++dropped_;
    ++dropped_by_channel_[victim->channel_id];
    erase(victim);
  }
}

std::optional<Frame> SendQueue::pop() {
  if (frames_.empty()) return std::nullopt;
  Frame frame = std::move(frames_.front());
  frames_.pop_front();
  bytes_ -= frame.size();
  return frame;
}

std::deque<Frame>::iterator SendQueue::oldest_sample(std::optional<uint32_t> channel_id) {
  const auto newest = frames_.end() - 1;
  for (auto it = frames_.begin(); it != newest; ++it)
    if (it->kind == Frame::Kind::Sample && (!channel_id || it->channel_id == *channel_id)) return it;
  return frames_.end();
}

std::deque<Frame>::iterator SendQueue::erase(std::deque<Frame>::iterator frame) {
  bytes_ -= frame->size();
  return frames_.erase(frame);
}

}  // namespace scanbus::foxglove_bridge

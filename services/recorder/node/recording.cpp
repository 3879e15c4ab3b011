#include "recording.hpp"

#include <chrono>

#include "scanbus/clock.hpp"
#include "scanbus/recorder/ros2msg.hpp"
#include "topic_channels.hpp"

namespace scanbus::recorder {

std::string catalogue_topic(const std::string& name) {
  const std::string topic = dds_topic_of_ros_topic(name);
  if (!find_topic(topic))
    throw ConfigError("topic '" + name + "' is not in the topic catalogue (`scanbus topics` lists them)");
  return topic;
}

RecorderSettings recorder_settings_from_config(const Config& section) {
  RecorderSettings settings;
  settings.out = section.text("out", "");
  if (settings.out.empty()) section.missing("out");
  try {
    for (const auto& name : section.texts("topics")) settings.topics.push_back(catalogue_topic(name));
  } catch (const ConfigError& error) {
    section.fail("topics", error.what());
  }
  settings.writer.compression = compression_from_name(section.choice("compression", "zstd", {"zstd", "lz4", "none"}));
  settings.writer.chunk_size =
      static_cast<size_t>(section.number("chunk_size", settings.writer.chunk_size / 1048576.0, 0.001, 1024) * 1048576);
  settings.reliable = section.flag("reliable", settings.reliable);
  settings.flush_period = section.number("flush_period", settings.flush_period, 0.01, 3600);
  settings.queue_bytes =
      static_cast<size_t>(section.number("queue_size", settings.queue_bytes / 1048576.0, 1, 65536) * 1048576);
  return settings;
}

Recording::Recording(Participant& participant, const RecorderSettings& settings, std::shared_ptr<spdlog::logger> log)
    : participant_(participant), settings_(settings), log_(std::move(log)), writer_(settings.out, settings.writer) {
  std::vector<std::string> topics;
  for (const auto& name : settings.topics) topics.push_back(catalogue_topic(name));
  if (topics.empty())
    for (const auto& info : topic_catalogue()) topics.push_back(info.name);

  TopicChannels channels(writer_);
  for (const auto& topic : topics) {
    const TopicInfo& info = topic_info(topic);
    QosSettings qos = participant.qos(topic);
    if (!participant.has_qos_override(topic)) {
      qos.keep_all = true;
      qos.reliable = qos.reliable || settings.reliable;
    }
    const uint16_t channel = channels.add(topic);
    topic_of_channel_[channel] = topic;
    readers_.push_back(std::make_unique<RawReader>(
        participant, topic, info.type, qos,
        [this, channel](const RawSample& sample, const auto& sample_info) { enqueue(channel, sample, sample_info); }));
  }
  writer_.flush();  // schemas and channels are on disk before the first message
  thread_ = std::thread([this] { write_loop(); });
  log_->info("recording {} topics to {} ({} chunks)", topics.size(), settings_.out,
             compression_name(settings_.writer.compression).empty() ? "uncompressed"
                                                                    : compression_name(settings_.writer.compression));
}

Recording::~Recording() {
  try {
    stop();
  } catch (const std::exception& error) {
    log_->error("{}", error.what());
  }
}

void Recording::enqueue(uint16_t channel, const RawSample& sample, const eprosima::fastdds::dds::SampleInfo& info) {
  const uint64_t received = wall_clock_ns();
  std::unique_lock<std::mutex> lock(mutex_);
  // Back-pressure: a reliable writer waits for us rather than a sample being dropped.
  changed_.wait(lock, [&] { return queued_bytes_ < settings_.queue_bytes || stopping_ || !failure_.empty(); });
  if (!failure_.empty()) return;
  const uint64_t published = static_cast<uint64_t>(info.source_timestamp.to_ns());
  queue_.push_back(
      {channel, static_cast<uint32_t>(info.sample_identity.sequence_number().to64long()), received, published, sample});
  queued_bytes_ += sample.size();
  changed_.notify_all();
}

void Recording::write_loop() {
  auto last_flush = std::chrono::steady_clock::now();
  const auto flush_period = std::chrono::duration<double>(settings_.flush_period);
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    changed_.wait_for(lock, flush_period, [&] { return !queue_.empty() || stopping_; });
    if (queue_.empty() && stopping_) break;
    try {
      // Flushing inside the drain too: under steady load the queue never empties.
      while (!queue_.empty() && std::chrono::steady_clock::now() - last_flush < flush_period) {
        Pending next = std::move(queue_.front());
        queue_.pop_front();
        queued_bytes_ -= next.data.size();
        changed_.notify_all();
        lock.unlock();
        writer_.write(next.channel, next.sequence, next.log_time, next.publish_time, next.data.data(),
                      next.data.size());
        lock.lock();
        written_bytes_ += next.data.size();
        ++written_by_topic_[topic_of_channel_.at(next.channel)];
      }
      if (std::chrono::steady_clock::now() - last_flush >= flush_period) {
        lock.unlock();
        writer_.flush();
        lock.lock();
        last_flush = std::chrono::steady_clock::now();
      }
    } catch (const McapError& error) {
      if (!lock.owns_lock()) lock.lock();
      failure_ = error.what();
      queue_.clear();
      queued_bytes_ = 0;
      changed_.notify_all();
      log_->error("{}", failure_);
      break;
    }
  }
}

void Recording::stop() {
  if (!thread_.joinable()) return;
  readers_.clear();  // no more samples; the listeners are gone before the queue goes
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
  writer_.close();
  if (!failure_.empty()) throw McapError(failure_);
  log_->info("closed {}: {} messages, {} lost", settings_.out, writer_.statistics().message_count, lost());
}

std::string Recording::failure() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failure_;
}

uint64_t Recording::messages() const {
  std::lock_guard<std::mutex> lock(mutex_);
  uint64_t messages = 0;
  for (const auto& [topic, count] : written_by_topic_) messages += count;
  return messages;
}

uint64_t Recording::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return written_bytes_;
}

std::map<std::string, uint64_t> Recording::counts_by_topic() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return written_by_topic_;
}

std::map<std::string, uint64_t> Recording::lost_by_topic() const { return participant_.lost_by_topic(); }

uint64_t Recording::lost() const { return participant_.lost(); }

}  // namespace scanbus::recorder

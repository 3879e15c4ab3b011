#include "replay.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <set>
#include <thread>

#include "cdr.hpp"
#include "raw_endpoints.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/recorder/mcap.hpp"
#include "scanbus/recorder/mcap_reader.hpp"
#include "scanbus/recorder/ros2msg.hpp"
#include "scanbus/replay_pacer.hpp"
#include "scanbus/service.hpp"
#include "scanbus/typed_topics.hpp"

namespace scanbus::recorder {

namespace dds = eprosima::fastdds::dds;

namespace {

struct Stopped {};  // unwinds the message stream when a stop is requested

dds::DataWriterQos replay_qos(const std::string& topic) {
  const TopicInfo* known = find_topic(topic);
  QosSettings qos = known ? known->qos : QosSettings{};
  qos.reliable = true;  // a reliable writer serves reliable and best-effort readers alike
  qos.keep_all = !qos.transient_local;
  dds::DataWriterQos out = writer_qos(qos);
  if (qos.keep_all) {
    // A bounded queue (large clouds must not pile up in memory); a full one makes write()
    // wait for acknowledgements, which is the flow control.
    out.resource_limits().max_samples = 64;
    out.resource_limits().max_samples_per_instance = 64;
  }
  out.reliability().max_blocking_time = eprosima::fastrtps::Duration_t(0.2);
  return out;
}

// Whether a message lies between --start and --end (seconds after the file's first).
bool in_window(const ReplaySettings& settings, uint64_t first_time, uint64_t log_time) {
  const double after_start = (log_time - first_time) * 1e-9;
  return (!settings.start || after_start >= *settings.start) && (!settings.end || after_start <= *settings.end);
}

// The file's selected channels, message count and first log time, checking it whole
// (unless salvaging) before anything is published.
struct Survey {
  std::map<uint16_t, std::string> topic_of_channel;  // selected channels -> DDS topic
  std::map<uint16_t, std::string> type_of_channel;
  uint64_t messages = 0;
  uint64_t first_time = UINT64_MAX;  // of any message, selected or not
  std::string damage;
};

Survey survey(const ReplaySettings& settings, const std::shared_ptr<spdlog::logger>& log) {
  std::vector<std::string> wanted;
  for (const auto& name : settings.topics) wanted.push_back(dds_topic_of_ros_topic(name));
  Survey result;
  std::map<uint16_t, bool> selected;
  McapReader reader(settings.file, settings.max_chunk);
  std::vector<uint64_t> times;  // of the selected channels' messages
  result.damage = reader.read_messages(
      [&](const McapMessage& message, const McapChannel& channel) {
        result.first_time = std::min(result.first_time, message.log_time);
        if (!selected.count(channel.id)) {
          const std::string topic = dds_topic_of_ros_topic(channel.topic);
          bool use = wanted.empty() || std::find(wanted.begin(), wanted.end(), topic) != wanted.end();
          const auto& schemas = reader.schemas();
          if (use && (channel.message_encoding != "cdr" || !schemas.count(channel.schema_id))) {
            log->warn("{}: channel '{}' is not CDR with a schema; not replayed", settings.file, channel.topic);
            use = false;
          }
          selected[channel.id] = use;
          if (use) {
            result.topic_of_channel[channel.id] = topic;
            result.type_of_channel[channel.id] = dds_type_of_ros_type(schemas.at(channel.schema_id).name);
          }
        }
        if (selected[channel.id]) times.push_back(message.log_time);
      },
      settings.salvage);
  for (const uint64_t time : times) result.messages += in_window(settings, result.first_time, time);
  for (const auto& name : wanted) {
    bool found = false;
    for (const auto& [channel, topic] : result.topic_of_channel) found = found || topic == name;
    if (!found) log->warn("{}: no channel carries {}", settings.file, name);
  }
  return result;
}

// rt/clock for --clock, unless the file's own /clock is replayed (two clocks would disagree).
std::unique_ptr<RawWriter> clock_writer(Participant& participant, const ReplaySettings& settings, const Survey& plan,
                                        spdlog::logger& log) {
  if (!settings.clock) return nullptr;
  for (const auto& [channel, topic] : plan.topic_of_channel)
    if (topic == topics::kClock.name) {
      log.info("{}: replaying the file's own {}", settings.file, topics::kClock.name);
      return nullptr;
    }
  const TopicInfo& info = topic_info(topics::kClock.name);
  return std::make_unique<RawWriter>(participant, info.name, info.type, writer_qos(info.qos));
}

RawSample clock_sample(uint64_t log_time) {
  rosgraph_msgs::msg::Clock clock;
  clock.clock(stamp_of_nanoseconds(log_time));
  return to_cdr<rosgraph_msgs::msg::ClockPubSubType>(clock);
}

}  // namespace

ReplayResult replay(Participant& participant, const ReplaySettings& settings, std::shared_ptr<spdlog::logger> log,
                    const std::function<void(uint64_t, uint64_t)>& progress) {
  if (settings.start && settings.end && *settings.end < *settings.start)
    throw McapError("replay: --end " + std::to_string(*settings.end) + " is before --start " +
                    std::to_string(*settings.start));
  const Survey plan = survey(settings, log);
  ReplayResult result;
  result.damage = plan.damage;
  if (!plan.damage.empty()) log->warn("salvaging: {}", plan.damage);
  if (plan.messages == 0) {
    log->warn("{}: no messages to replay (topics, --start and --end select none)", settings.file);
    return result;
  }

  std::map<uint16_t, std::unique_ptr<RawWriter>> writers;
  std::set<uint16_t> latched;  // channels whose writer keeps only the last samples
  for (const auto& [channel, topic] : plan.topic_of_channel) {
    const dds::DataWriterQos qos = replay_qos(topic);
    writers[channel] = std::make_unique<RawWriter>(participant, topic, plan.type_of_channel.at(channel), qos);
    if (qos.history().kind == dds::KEEP_LAST_HISTORY_QOS) latched.insert(channel);
  }
  const std::unique_ptr<RawWriter> clock = clock_writer(participant, settings, plan, *log);
  const auto wait_deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(settings.wait_timeout);
  // False when a stop was requested meanwhile.
  const auto wait_for_readers = [&](const RawWriter& writer, size_t count) {
    while (writer.matched_readers() < count && std::chrono::steady_clock::now() < wait_deadline)
      if (StopSignal::wait_for(std::chrono::milliseconds(20))) return false;
    if (writer.matched_readers() < count)
      log->warn("{}: {} of {} readers after {} s; replaying anyway", writer.topic(), writer.matched_readers(), count,
                settings.wait_timeout);
    return true;
  };
  for (const auto& [channel, writer] : writers)
    if (!wait_for_readers(*writer, settings.wait_for_readers)) return result;
  // Whoever follows the clock hears it before the first message (not every reader of the data does).
  if (clock && !wait_for_readers(*clock, std::min<size_t>(settings.wait_for_readers, 1))) return result;

  // A message whose stamp jumps waits for the next to tell a broken stamp from a pause
  // (ReplayPacer), its bytes copied out of the chunk.
  struct Held {
    RawSample data;
    uint16_t channel;
    uint64_t log_time;
  };
  std::optional<Held> held;
  std::chrono::steady_clock::time_point first_published;
  uint64_t clock_time = 0;  // the last published on rt/clock: it never goes back within a pass
  const auto publish = [&](const RawSample& sample, uint16_t channel, uint64_t log_time) {
    if (clock && log_time > clock_time) clock->write(clock_sample(clock_time = log_time));
    RawWriter& writer = *writers.at(channel);
    RawWriter::Result written;
    while ((written = writer.write(sample)) == RawWriter::Result::QueueFull) {
      if (StopSignal::requested()) throw Stopped{};  // readers slow: keep waiting, lose nothing
    }
    if (written == RawWriter::Result::Refused) {
      if (result.skipped++ == 0)
        log->warn("{}: a message of {} bytes on {} cannot be published (not CDR?); skipping such messages",
                  settings.file, sample.size(), writer.topic());
      return;
    }
    // A transient-local writer keeps its catalogue depth (late joiners get the last
    // samples): its next write would replace a sample not yet acknowledged, lost to a
    // reader still catching up (a room's three scan clouds at --rate 0 under load).
    if (latched.count(channel))
      while (!writer.wait_for_acknowledgments(std::chrono::milliseconds(200)))
        if (StopSignal::requested()) throw Stopped{};
    const auto now = std::chrono::steady_clock::now();
    if (result.published == 0) first_published = now;
    result.span = std::chrono::duration<double>(now - first_published).count();
    ++result.published;
    ++result.published_by_topic[writer.topic()];
    if (progress) progress(result.published, plan.messages);
  };
  const auto report_skipped = [&](const ReplayPacer& pacer) {
    if (pacer.skipped() == 1 && result.stamps_skipped == 0)
      log->warn("{}: a message's stamp jumps more than {} s from its neighbours'; skipping such messages",
                settings.file, settings.max_gap);
  };
  RawSample sample;
  try {
    do {
      clock_time = 0;  // a --loop pass starts the recording's time again
      const auto wall_start = std::chrono::steady_clock::now();
      ReplayPacer pacer(settings.rate, settings.max_gap);
      McapReader reader(settings.file, settings.max_chunk);
      reader.read_messages(
          [&](const McapMessage& message, const McapChannel& channel) {
            if (!writers.count(channel.id)) return;
            if (!in_window(settings, plan.first_time, message.log_time)) return;
            const auto step = pacer.next(message.log_time * 1e-9);
            if (step.skip_held) report_skipped(pacer);
            if (step.publish_held) publish(held->data, held->channel, held->log_time);
            held.reset();
            sample.assign(message.data, message.data + message.size);
            if (step.hold) {
              held = Held{sample, channel.id, message.log_time};
              return;
            }
            const auto due = wall_start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                              std::chrono::duration<double>(step.due));
            while (std::chrono::steady_clock::now() < due) {
              if (StopSignal::requested()) throw Stopped{};
              std::this_thread::sleep_until(
                  std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(50)));
            }
            publish(sample, channel.id, message.log_time);
          },
          true);  // damage was found (and reported) by the survey
      if (pacer.finish()) report_skipped(pacer);
      held.reset();
      result.stamps_skipped += pacer.skipped();
      result.pauses += pacer.pauses();
    } while (settings.loop && !StopSignal::requested());
  } catch (const Stopped&) {
    log->info("stopped after {} messages", result.published);
  }
  for (const auto& [channel, writer] : writers) {
    if (!writer->wait_for_acknowledgments(std::chrono::seconds(5)))
      log->warn("{}: readers did not acknowledge every sample within 5 s", writer->topic());
  }
  linger_for_lagging_readers(settings.linger);
  return result;
}

}  // namespace scanbus::recorder

// A recording in progress: a raw reader per topic (catalogue QoS, KEEP_ALL unless the
// config's qos section says otherwise) feeding a bounded queue that one thread writes to
// an MCAP file (ros2 profile, cdr messages, ros2msg schemas). A full queue blocks the DDS
// listener instead of dropping, so reliable KEEP_ALL writers are slowed, never lose samples.
// Samples that never reached the recorder (a best-effort writer outrunning it, a KEEP_LAST
// queue overflowing) show as gaps in their writer's sequence numbers: counted as lost.
#pragma once

#include <spdlog/spdlog.h>

#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "raw_endpoints.hpp"
#include "scanbus/recorder/mcap_writer.hpp"

namespace scanbus::recorder {

struct RecorderSettings {
  std::string out;                  // the MCAP file
  std::vector<std::string> topics;  // DDS names; empty: every topic of the catalogue
  bool reliable = false;            // every topic RELIABLE (best-effort writers then do not match)
  McapWriterOptions writer;
  double flush_period = 1.0;        // s: the open chunk reaches the file at least this often
  size_t queue_bytes = 256u << 20;  // samples waiting for the file before readers block
};

// Section `recorder` of config/services/recorder.yaml.
RecorderSettings recorder_settings_from_config(const Config& section);
// "rt/scan" or "/scan" -> "rt/scan"; throws ConfigError for topics not in the catalogue.
std::string catalogue_topic(const std::string& name);

class Recording {
 public:
  Recording(Participant& participant, const RecorderSettings& settings, std::shared_ptr<spdlog::logger> log);
  ~Recording();
  Recording(const Recording&) = delete;
  Recording& operator=(const Recording&) = delete;

  // Stops the readers, writes what is queued and closes a valid file; idempotent.
  void stop();
  // The writing thread's error (the file system full, say); empty while all is well. After
  // one, samples are no longer recorded and stop() throws it.
  std::string failure() const;
  uint64_t messages() const;
  uint64_t bytes() const;
  std::map<std::string, uint64_t> counts_by_topic() const;
  // Samples lost before reaching the recorder, by topic (topics without loss absent): the
  // participant's count, so give the recording a participant of its own.
  std::map<std::string, uint64_t> lost_by_topic() const;
  uint64_t lost() const;

 private:
  struct Pending {
    uint16_t channel;
    uint32_t sequence;
    uint64_t log_time, publish_time;
    RawSample data;
  };
  void enqueue(uint16_t channel, const RawSample& sample, const eprosima::fastdds::dds::SampleInfo& info);
  void write_loop();

  Participant& participant_;  // counts what its readers lost
  RecorderSettings settings_;
  std::shared_ptr<spdlog::logger> log_;
  McapWriter writer_;
  std::map<uint16_t, std::string> topic_of_channel_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Pending> queue_;
  size_t queued_bytes_ = 0;
  bool stopping_ = false;
  uint64_t written_bytes_ = 0;
  std::map<std::string, uint64_t> written_by_topic_;
  std::string failure_;  // the writer thread's error, reported by stop()
  std::vector<std::unique_ptr<RawReader>> readers_;
  std::thread thread_;
};

}  // namespace scanbus::recorder

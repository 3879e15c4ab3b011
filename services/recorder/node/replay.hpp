// Publishes an MCAP file's CDR messages on their DDS topics, byte for byte, with the
// recorded timing scaled by a rate or as fast as the readers take them: writers are
// RELIABLE with KEEP_ALL history (a bounded queue, then write() waits for
// acknowledgements), so a reliable subscriber loses nothing at any speed. Latched
// (transient local) topics keep their catalogue depth instead, for late joiners.
#pragma once

#include <spdlog/spdlog.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scanbus/dds.hpp"
#include "scanbus/recorder/mcap_reader.hpp"

namespace scanbus::recorder {

struct ReplaySettings {
  std::string file;
  double rate = 1.0;  // times the recorded pace (at least 0.001); 0 = as fast as possible
  bool loop = false;
  std::vector<std::string> topics;   // DDS or ROS names; empty: every channel
  std::optional<double> start, end;  // s after the file's first message
  bool salvage = false;              // replay what precedes damage instead of refusing the file
  size_t wait_for_readers = 0;       // readers every replayed topic must have before the first message
  double wait_timeout = 10;          // s to wait for them at most
  double max_gap = 60;               // s a stamp may jump from the previous (ReplayPacer)
  double linger = 3;                 // s kept alive after the end, for readers behind (linger_for_lagging_readers)
  bool clock = false;  // rt/clock at each message's log time (ros2 bag play --clock), unless the file has one
  uint64_t max_chunk = McapReader::kDefaultMaxRecord;  // bytes one record may take in memory
};

struct ReplayResult {
  uint64_t published = 0;
  uint64_t skipped = 0;                                // messages DDS would not take (not CDR)
  std::map<std::string, uint64_t> published_by_topic;  // DDS names
  std::string damage;                                  // with salvage: what ended the file early
  uint64_t stamps_skipped = 0;                         // messages whose stamp jumped alone (broken)
  uint64_t pauses = 0;                                 // gaps over max_gap replayed without waiting
  double span = 0;                                     // s from the first message published to the last
                                                       // (the pace; not the wait for readers' acks after)
};

// Throws McapError for a damaged file (unless salvage) and DdsError; returns early, with
// what went out, when a stop is requested (StopSignal).
ReplayResult replay(Participant& participant, const ReplaySettings& settings, std::shared_ptr<spdlog::logger> log,
                    const std::function<void(uint64_t done, uint64_t total)>& progress = {});

}  // namespace scanbus::recorder

// `scanbus record`, `scanbus replay`, `scanbus info`: MCAP recordings of scanbus topics.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <set>

#include "commands.hpp"
#include "recording.hpp"
#include "replay.hpp"
#include "scanbus/recorder/mcap_reader.hpp"
#include "scanbus/recorder/ros2msg.hpp"
#include "scanbus/service.hpp"

namespace scanbus::cli {

namespace {

using recorder::McapError;

uint64_t mebibytes(double mib) { return static_cast<uint64_t>(mib * (1 << 20)); }

// --max-chunk: what one MCAP record may take in memory (McapReader::kDefaultMaxRecord).
void add_max_chunk(CLI::App* command, double& mib) {
  command->add_option("--max-chunk", mib, "MiB one chunk of the file may take in memory, uncompressed")
      ->check(CLI::Range(1.0, 1048576.0));
}

struct RecordOptions {
  DdsOptions dds;
  std::vector<std::string> topics;
  std::string out;
  std::string compression = "zstd";
  double chunk_size = 4.0;
  double duration = 0;
  bool reliable = false;
  bool json = false;
  double queue_size = 256;  // MiB
};

int run_record(const RecordOptions& options) {
  StopSignal::install();
  recorder::RecorderSettings settings;
  settings.out = options.out;
  settings.topics = options.topics;  // checked against the catalogue by Recording
  settings.reliable = options.reliable;
  settings.writer.compression = recorder::compression_from_name(options.compression);
  settings.writer.chunk_size = static_cast<size_t>(options.chunk_size * 1048576);
  settings.queue_bytes = static_cast<size_t>(options.queue_size * 1048576);
  auto log = make_logger("record", options.json ? "warn" : "info");
  Participant participant(options.dds.settings(), "scanbus/record");
  recorder::Recording recording(participant, settings, log);
  const bool progress = !options.json && isatty(STDOUT_FILENO);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.duration);
  while (!StopSignal::wait_for(std::chrono::milliseconds(200)) && recording.failure().empty()) {
    if (progress)
      std::printf("\rrecording: %lu messages, %.1f MB, %lu lost", static_cast<unsigned long>(recording.messages()),
                  recording.bytes() / 1e6, static_cast<unsigned long>(recording.lost())),
          std::fflush(stdout);
    if (options.duration > 0 && std::chrono::steady_clock::now() > deadline) break;
  }
  if (progress) std::printf("\r%60s\r", "");
  if (!recording.failure().empty()) {
    std::cerr << "scanbus record: " << recording.failure() << " (" << recording.messages()
              << " messages recorded before)\n";
    return 1;
  }
  recording.stop();
  const auto counts = recording.counts_by_topic();
  if (options.json) {
    std::cout << nlohmann::json{{"file", options.out},        {"messages", recording.messages()},
                                {"bytes", recording.bytes()}, {"topics", counts},
                                {"lost", recording.lost()},   {"lost_by_topic", recording.lost_by_topic()}}
                     .dump()
              << "\n";
  } else {
    std::cout << options.out << ": " << recording.messages() << " messages, " << recording.lost() << " lost\n";
    const auto lost = recording.lost_by_topic();
    for (const auto& [topic, count] : counts)
      std::cout << "  " << topic << ": " << count
                << (lost.count(topic) ? ", " + std::to_string(lost.at(topic)) + " lost" : "") << "\n";
  }
  return 0;
}

struct ReplayOptions {
  DdsOptions dds;
  recorder::ReplaySettings settings;
  double max_chunk_mib = recorder::McapReader::kDefaultMaxRecord >> 20;
  double start = -1, end = -1;
  bool json = false;
};

int run_replay(ReplayOptions options) {
  StopSignal::install();
  if (options.settings.rate > 0 && options.settings.rate < 0.001)
    throw ConfigError("--rate: 0 (as fast as possible) or at least 0.001, got " +
                      std::to_string(options.settings.rate));
  options.settings.max_chunk = mebibytes(options.max_chunk_mib);
  if (options.start >= 0) options.settings.start = options.start;
  if (options.end >= 0) options.settings.end = options.end;
  auto log = make_logger("replay", options.json ? "warn" : "info");
  Participant participant(options.dds.settings(), "scanbus/replay");
  const bool progress = !options.json && isatty(STDOUT_FILENO);
  const auto result = recorder::replay(participant, options.settings, log, [&](uint64_t done, uint64_t total) {
    if (progress && (done % 50 == 0 || done == total))
      std::printf("\rreplaying: message %lu of %lu", static_cast<unsigned long>(done),
                  static_cast<unsigned long>(total)),
          std::fflush(stdout);
  });
  if (progress) std::printf("\r%60s\r", "");
  if (options.json) {
    std::cout << nlohmann::json{{"file", options.settings.file},
                                {"published", result.published},
                                {"topics", result.published_by_topic},
                                {"damage", result.damage},
                                {"stamps_skipped", result.stamps_skipped},
                                {"pauses", result.pauses},
                                {"span_s", result.span}}
                     .dump()
              << "\n";
  } else {
    std::cout << options.settings.file << ": published " << result.published << " messages over " << result.span
              << " s\n";
    for (const auto& [topic, count] : result.published_by_topic) std::cout << "  " << topic << ": " << count << "\n";
    if (!result.damage.empty()) std::cout << "stopped at damage: " << result.damage << "\n";
    if (result.stamps_skipped)
      std::cout << "skipped " << result.stamps_skipped << " messages whose stamps jumped more than --max-gap\n";
    if (result.pauses) std::cout << "replayed " << result.pauses << " pauses over --max-gap without waiting\n";
  }
  return 0;
}

struct InfoOptions {
  std::string file;
  double max_chunk_mib = recorder::McapReader::kDefaultMaxRecord >> 20;
  bool salvage = false;
  bool json = false;
};

// From the summary when the file has one, else by reading every message.
int run_info(const InfoOptions& options) {
  recorder::McapReader reader(options.file, mebibytes(options.max_chunk_mib));
  std::map<uint16_t, recorder::McapChannel> channels;
  std::map<uint16_t, recorder::McapSchema> schemas;
  std::map<uint16_t, uint64_t> counts;
  uint64_t messages = 0, start = 0, end = 0, chunks = 0;
  std::set<std::string> compressions;
  std::string damage;
  const auto summary = reader.read_summary();
  if (summary && summary->statistics) {
    channels = summary->channels;
    schemas = summary->schemas;
    counts = summary->statistics->channel_message_counts;
    messages = summary->statistics->message_count;
    start = summary->statistics->message_start_time;
    end = summary->statistics->message_end_time;
    chunks = summary->chunks.size();
    for (const auto& chunk : summary->chunks)
      compressions.insert(chunk.compression.empty() ? "none" : chunk.compression);
  } else {
    damage = reader.read_messages(
        [&](const recorder::McapMessage& message, const recorder::McapChannel&) {
          start = messages == 0 ? message.log_time : std::min(start, message.log_time);
          end = std::max(end, message.log_time);
          ++messages;
          ++counts[message.channel_id];
        },
        options.salvage);
    channels = reader.channels();
    schemas = reader.schemas();
  }
  const double duration = messages ? (end - start) * 1e-9 : 0;
  nlohmann::json topics = nlohmann::json::array();
  for (const auto& [id, channel] : channels) {
    const auto schema = schemas.find(channel.schema_id);
    topics.push_back({{"topic", channel.topic},
                      {"type", schema == schemas.end() ? "" : schema->second.name},
                      {"message_encoding", channel.message_encoding},
                      {"messages", counts.count(id) ? counts.at(id) : 0}});
  }
  if (options.json) {
    std::cout << nlohmann::json{{"file", options.file},
                                {"bytes", reader.file_size()},
                                {"profile", reader.profile()},
                                {"library", reader.library()},
                                {"messages", messages},
                                {"start_ns", start},
                                {"end_ns", end},
                                {"duration_s", duration},
                                {"chunks", chunks},
                                {"compression", compressions},
                                {"topics", topics},
                                {"damage", damage}}
                     .dump()
              << "\n";
    return 0;
  }
  std::printf("%s: %lu bytes, profile '%s', written by '%s'\n", options.file.c_str(),
              static_cast<unsigned long>(reader.file_size()), reader.profile().c_str(), reader.library().c_str());
  std::printf("messages: %lu over %.3f s\n", static_cast<unsigned long>(messages), duration);
  if (!summary || !summary->statistics) {
    std::printf("no summary: counted by reading every message\n");
  } else if (chunks) {
    std::string names;
    for (const auto& name : compressions) names += (names.empty() ? "" : ", ") + name;
    std::printf("chunks: %lu (%s)\n", static_cast<unsigned long>(chunks), names.c_str());
  }
  for (const auto& topic : topics) {
    const auto count = topic["messages"].get<uint64_t>();
    std::printf("  %-28s %-44s %8lu msgs\n", topic["topic"].get<std::string>().c_str(),
                topic["type"].get<std::string>().c_str(), static_cast<unsigned long>(count));
  }
  if (!damage.empty()) std::printf("damaged: %s\n", damage.c_str());
  return 0;
}

// Bad input (an unknown topic, a damaged or missing file) exits 2 like a bad command line,
// with its one-line message; failures at run time stay 1.
int input_errors_exit_2(const char* name, const std::function<int()>& body) {
  try {
    return body();
  } catch (const ConfigError& e) {
    std::cerr << "scanbus " << name << ": " << e.what() << "\n";
  } catch (const McapError& e) {
    std::cerr << "scanbus " << name << ": " << e.what() << "\n";
  }
  return 2;
}

}  // namespace

void add_record_commands(CLI::App& app, int& exit_code) {
  static RecordOptions record;
  auto* command = app.add_subcommand("record", "Record topics to an MCAP file (ros2 profile) until Ctrl-C");
  command->add_option("--topics", record.topics,
                      "Topics, DDS (rt/scan) or ROS (/scan) names (default: every catalogue topic)");
  command->add_option("-o,--out", record.out, "MCAP file to write")->required();
  command->add_option("--compression", record.compression, "Chunk compression")
      ->check(CLI::IsMember({"zstd", "lz4", "none"}));
  command->add_option("--chunk-size", record.chunk_size, "MiB of messages per chunk")->check(CLI::Range(0.001, 1024.0));
  command->add_option("--duration", record.duration, "Stop after this many seconds (0: at Ctrl-C or SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--reliable", record.reliable,
                    "Read every topic RELIABLE (default: as the catalogue; sensor topics are best effort)");
  command->add_option("--queue-size", record.queue_size, "MiB of samples waiting for the file before readers block")
      ->check(CLI::Range(0.001, 65536.0));
  command->add_flag("--json", record.json, "One JSON summary line, no progress");
  add_dds_options(*command, record.dds);
  on_run(*command, exit_code, [] { return input_errors_exit_2("record", [] { return run_record(record); }); });

  static ReplayOptions replay;
  command = app.add_subcommand("replay", "Publish an MCAP file's messages on their topics");
  command->add_option("file", replay.settings.file, "MCAP file")->required()->check(CLI::ExistingFile);
  command->add_option("--rate", replay.settings.rate, "Times the recorded pace (0: as fast as readers take them)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--loop", replay.settings.loop, "Start again at the end, until Ctrl-C");
  command->add_option("--topics", replay.settings.topics, "Only these topics (DDS or ROS names)")->delimiter(',');
  command->add_flag("--clock", replay.settings.clock,
                    "Publish the recording's time on rt/clock at each message (as ros2 bag play --clock), for "
                    "tools that follow it (foxglove_bridge with sim_time, ROS 2 with use_sim_time)");
  command->add_option("--start", replay.start, "Seconds after the first message to start at")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--end", replay.end, "Seconds after the first message to stop at")->check(CLI::NonNegativeNumber);
  command->add_flag("--salvage", replay.settings.salvage, "Replay what precedes damage instead of refusing the file");
  command
      ->add_option("--max-gap", replay.settings.max_gap,
                   "Seconds a stamp may jump from the previous message's: one alone is skipped, a pause not waited")
      ->check(CLI::PositiveNumber);
  add_max_chunk(command, replay.max_chunk_mib);
  command->add_option("--wait-for-readers", replay.settings.wait_for_readers,
                      "Readers every replayed topic must have before the first message");
  command->add_option("--wait-timeout", replay.settings.wait_timeout, "Seconds to wait for those readers at most")
      ->check(CLI::NonNegativeNumber);
  command
      ->add_option("--linger", replay.settings.linger,
                   "Seconds to stay after the last message, so that readers behind it can still read it")
      ->check(CLI::Range(0.0, 600.0));
  command->add_flag("--json", replay.json, "One JSON summary line, no progress");
  add_dds_options(*command, replay.dds);
  on_run(*command, exit_code, [] { return input_errors_exit_2("replay", [] { return run_replay(replay); }); });

  static InfoOptions info;
  command = app.add_subcommand("info", "Topics, types, counts and time span of an MCAP file");
  command->add_option("file", info.file, "MCAP file")->required()->check(CLI::ExistingFile);
  command->add_flag("--salvage", info.salvage, "Report what precedes damage instead of refusing the file");
  add_max_chunk(command, info.max_chunk_mib);
  command->add_flag("--json", info.json, "One JSON object");
  on_run(*command, exit_code, [] { return input_errors_exit_2("info", [] { return run_info(info); }); });
}

}  // namespace scanbus::cli

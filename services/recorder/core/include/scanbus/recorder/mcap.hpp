// MCAP (https://mcap.dev/spec), the container rosbag2, eProsima's DDS Record & Replay and
// Foxglove use for recordings: its records as this project writes and reads them. Debian
// packages no C++ MCAP library, so scanbus has its own (mcap_writer.hpp, mcap_reader.hpp).
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

namespace scanbus::recorder {

// A malformed, truncated or unreadable file; the message names the file offset.
class McapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Files whose name ends in .mcap are read as recordings where a tool also takes text logs.
inline bool is_mcap_path(const std::string& path) {
  return path.size() > 5 && path.compare(path.size() - 5, 5, ".mcap") == 0;
}

enum class Compression { None, Lz4, Zstd };
// "" / "lz4" / "zstd": the spec's names, also the command line's ("none" for "").
std::string compression_name(Compression compression);
Compression compression_from_name(const std::string& name);  // throws McapError on others

struct McapSchema {
  uint16_t id = 0;
  std::string name;      // e.g. sensor_msgs/msg/LaserScan
  std::string encoding;  // e.g. ros2msg
  std::string data;
};

struct McapChannel {
  uint16_t id = 0;
  uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;  // e.g. cdr
  std::map<std::string, std::string> metadata;
};

struct McapMessage {
  uint16_t channel_id = 0;
  uint32_t sequence = 0;
  uint64_t log_time = 0;          // ns since the epoch
  uint64_t publish_time = 0;      // ns since the epoch
  const uint8_t* data = nullptr;  // valid during the callback that receives it
  size_t size = 0;
};

// The Statistics record's content.
struct McapStatistics {
  uint64_t message_count = 0;
  uint16_t schema_count = 0;
  uint32_t channel_count = 0;
  uint32_t chunk_count = 0;
  uint64_t message_start_time = 0;
  uint64_t message_end_time = 0;
  std::map<uint16_t, uint64_t> channel_message_counts;
};

namespace mcap_format {
constexpr char kMagic[8] = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};
enum Opcode : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};
}  // namespace mcap_format

}  // namespace scanbus::recorder

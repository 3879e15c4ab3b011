// Reads an MCAP file: its summary (from the footer) when present, and its messages in
// file order by streaming the data section, chunk by chunk. Every length is checked
// against the file before it is trusted, chunks against their CRC, the data section
// against the Data End CRC; damage is an McapError naming the offset. In salvage mode the
// messages before the damage are delivered and the damage is reported, not thrown.
#pragma once

#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scanbus/recorder/mcap.hpp"

namespace scanbus::recorder {

struct McapChunkInfo {
  uint64_t offset = 0;
  uint64_t start_time = 0, end_time = 0;
  std::string compression;
  uint64_t compressed_size = 0, uncompressed_size = 0;
};

struct McapSummary {
  std::map<uint16_t, McapSchema> schemas;
  std::map<uint16_t, McapChannel> channels;
  std::optional<McapStatistics> statistics;
  std::vector<McapChunkInfo> chunks;
};

class McapReader {
 public:
  using MessageHandler = std::function<void(const McapMessage&, const McapChannel&)>;

  // The most one record (a chunk compressed or uncompressed, the summary) may take in
  // memory: a chunk may claim gigabytes, and zstd or lz4 can legitimately expand that far.
  // Our recorder's chunks are a few MiB; a file over the budget is refused naming the
  // offset and both sizes, and a user who trusts it raises the budget (`--max-chunk`).
  static constexpr uint64_t kDefaultMaxRecord = uint64_t{1} << 30;  // 1 GiB

  // Opens the file and checks the leading magic and header; throws McapError.
  explicit McapReader(const std::string& path, uint64_t max_record = kDefaultMaxRecord);
  ~McapReader();
  McapReader(const McapReader&) = delete;
  McapReader& operator=(const McapReader&) = delete;

  const std::string& profile() const { return profile_; }
  const std::string& library() const { return library_; }
  uint64_t file_size() const { return file_size_; }

  // The summary section, or nothing when the file has none (cut short, or written
  // without). Throws McapError when the footer is there but the summary is damaged.
  std::optional<McapSummary> read_summary();

  // Streams the data section, calling `on_message` for each message in file order.
  // Damage throws McapError, or with `salvage` ends the stream and is returned (empty
  // when the file read cleanly to its end).
  std::string read_messages(const MessageHandler& on_message, bool salvage = false);

  // Schemas and channels met so far by read_messages().
  const std::map<uint16_t, McapSchema>& schemas() const { return schemas_; }
  const std::map<uint16_t, McapChannel>& channels() const { return channels_; }
  // Metadata records met so far by read_messages(), by name.
  const std::map<std::string, std::map<std::string, std::string>>& metadata() const { return metadata_; }

 private:
  void open_checked();  // the constructor's checks, after fopen
  void stream(const MessageHandler& on_message);
  void read_at(uint64_t offset, void* out, size_t size, const char* what);
  void handle_record(uint8_t opcode, const uint8_t* content, size_t size, uint64_t offset,
                     const MessageHandler& on_message);
  void handle_chunk(const uint8_t* content, size_t size, uint64_t offset, const MessageHandler& on_message);
  void check_budget(uint64_t size, const std::string& what) const;

  std::string path_;
  uint64_t max_record_;
  std::FILE* file_ = nullptr;
  uint64_t file_size_ = 0;
  uint64_t data_start_ = 0;  // after the header record
  std::string profile_, library_;
  std::map<uint16_t, McapSchema> schemas_;
  std::map<uint16_t, McapChannel> channels_;
  std::map<std::string, std::map<std::string, std::string>> metadata_;
};

}  // namespace scanbus::recorder

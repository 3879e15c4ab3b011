// Writes an MCAP file: header, schemas and channels as they come (outside chunks, so a
// file cut short still names every channel its messages use), messages in compressed
// chunks each followed by its message indexes, and on close a summary (schemas,
// channels, statistics, chunk indexes), summary offsets and the footer.
//
// A chunk goes to the file when it reaches `chunk_size` or on flush(); what reached the
// file survives a killed process and reads back with McapReader's salvage mode.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "scanbus/recorder/mcap.hpp"

namespace scanbus::recorder {

struct McapWriterOptions {
  Compression compression = Compression::Zstd;
  size_t chunk_size = 4 << 20;  // bytes of uncompressed records per chunk
  std::string profile = "ros2";
  std::string library = "scanbus";
};

class McapWriter {
 public:
  // Creates (truncates) the file and writes the magic and header; throws McapError.
  McapWriter(const std::string& path, McapWriterOptions options);
  // Closes the file if close() was not called; errors then go unreported.
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Ids are given in order from 1 (schema id 0 means "no schema").
  uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  uint16_t add_channel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                       const std::map<std::string, std::string>& metadata);
  // A Metadata record (name and key-value pairs), indexed in the summary.
  void add_metadata(const std::string& name, const std::map<std::string, std::string>& entries);
  void write(uint16_t channel_id, uint32_t sequence, uint64_t log_time, uint64_t publish_time, const uint8_t* data,
             size_t size);
  // Writes the open chunk (if any) and hands everything to the operating system.
  void flush();
  // Writes the open chunk, the summary and the footer, and closes the file.
  void close();

  const McapStatistics& statistics() const { return statistics_; }
  uint64_t bytes_written() const { return offset_; }

 private:
  struct ChunkIndex {
    uint64_t start_time, end_time, offset, length;
    std::map<uint16_t, uint64_t> message_index_offsets;
    uint64_t message_index_length, compressed_size, uncompressed_size;
  };
  void check_writable() const;
  void emit(const std::vector<uint8_t>& bytes);
  void write_chunk();
  std::vector<uint8_t> summary_section(uint64_t summary_start, std::vector<uint8_t>& offsets_section) const;

  std::string path_;
  McapWriterOptions options_;
  std::FILE* file_ = nullptr;
  uint64_t offset_ = 0;
  bool failed_ = false;
  uint32_t data_crc_ = 0;  // of every byte written so far, for the Data End record
  std::vector<McapSchema> schemas_;
  std::vector<McapChannel> channels_;
  McapStatistics statistics_;
  std::vector<ChunkIndex> chunk_indexes_;
  struct MetadataIndex {
    uint64_t offset, length;
    std::string name;
  };
  std::vector<MetadataIndex> metadata_indexes_;
  // The open chunk: its records, time span and each channel's (log time, offset) index.
  std::vector<uint8_t> chunk_records_;
  uint64_t chunk_start_time_ = 0, chunk_end_time_ = 0;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_message_index_;
};

}  // namespace scanbus::recorder

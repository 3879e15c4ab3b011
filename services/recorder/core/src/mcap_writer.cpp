#include "scanbus/recorder/mcap_writer.hpp"

#include <cerrno>
#include <cstring>
#include <limits>

#include "mcap_bytes.hpp"

namespace scanbus::recorder {

using namespace mcap_bytes;
namespace format = mcap_format;

namespace {

Bytes schema_record(const McapSchema& schema) {
  Bytes content;
  put<uint16_t>(content, schema.id);
  put_string(content, schema.name);
  put_string(content, schema.encoding);
  put_string(content, schema.data);  // bytes with a u32 length, like a string
  Bytes record;
  put_record(record, format::kSchema, content);
  return record;
}

Bytes channel_record(const McapChannel& channel) {
  Bytes content;
  put<uint16_t>(content, channel.id);
  put<uint16_t>(content, channel.schema_id);
  put_string(content, channel.topic);
  put_string(content, channel.message_encoding);
  put_string_map(content, channel.metadata);
  Bytes record;
  put_record(record, format::kChannel, content);
  return record;
}

}  // namespace

McapWriter::McapWriter(const std::string& path, McapWriterOptions options) : path_(path), options_(std::move(options)) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw McapError(path + ": cannot create (" + std::strerror(errno) + ")");
  Bytes start(std::begin(format::kMagic), std::end(format::kMagic));
  Bytes header;
  put_string(header, options_.profile);
  put_string(header, options_.library);
  put_record(start, format::kHeader, header);
  emit(start);
}

McapWriter::~McapWriter() {
  if (!file_) return;
  try {
    close();
  } catch (const McapError&) {
    // A destructor cannot report; callers who care call close() themselves.
  }
  if (file_) std::fclose(file_);  // after a failed write: what reached the file stays as it is
}

void McapWriter::check_writable() const {
  if (!file_) throw McapError(path_ + ": written to after close");
  if (failed_) throw McapError(path_ + ": an earlier write failed; the file ends at offset " + std::to_string(offset_));
}

void McapWriter::emit(const Bytes& bytes) {
  check_writable();
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    failed_ = true;  // the file's tail is unknown now: no later record may claim an offset in it
    throw McapError(path_ + ": write failed at offset " + std::to_string(offset_) + " (" + std::strerror(errno) + ")");
  }
  data_crc_ = crc32_of(bytes.data(), bytes.size(), data_crc_);
  offset_ += bytes.size();
}

uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
  if (schemas_.size() >= std::numeric_limits<uint16_t>::max() - 1) throw McapError(path_ + ": too many schemas");
  schemas_.push_back({static_cast<uint16_t>(schemas_.size() + 1), name, encoding, data});
  emit(schema_record(schemas_.back()));
  statistics_.schema_count = static_cast<uint16_t>(schemas_.size());
  return schemas_.back().id;
}

uint16_t McapWriter::add_channel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                                 const std::map<std::string, std::string>& metadata) {
  if (schema_id > schemas_.size()) throw McapError(path_ + ": channel '" + topic + "' names an unknown schema");
  if (channels_.size() >= std::numeric_limits<uint16_t>::max() - 1) throw McapError(path_ + ": too many channels");
  channels_.push_back({static_cast<uint16_t>(channels_.size() + 1), schema_id, topic, message_encoding, metadata});
  emit(channel_record(channels_.back()));
  statistics_.channel_count = static_cast<uint32_t>(channels_.size());
  return channels_.back().id;
}

void McapWriter::add_metadata(const std::string& name, const std::map<std::string, std::string>& entries) {
  Bytes content;
  put_string(content, name);
  put_string_map(content, entries);
  Bytes record;
  put_record(record, format::kMetadata, content);
  metadata_indexes_.push_back({offset_, record.size(), name});
  emit(record);
}

void McapWriter::write(uint16_t channel_id, uint32_t sequence, uint64_t log_time, uint64_t publish_time,
                       const uint8_t* data, size_t size) {
  check_writable();
  if (channel_id == 0 || channel_id > channels_.size())
    throw McapError(path_ + ": message on unknown channel " + std::to_string(channel_id));
  if (chunk_records_.empty()) {
    chunk_start_time_ = log_time;
    chunk_end_time_ = log_time;
  }
  chunk_message_index_[channel_id].emplace_back(log_time, chunk_records_.size());
  put<uint8_t>(chunk_records_, format::kMessage);
  put<uint64_t>(chunk_records_, 2 + 4 + 8 + 8 + size);
  put<uint16_t>(chunk_records_, channel_id);
  put<uint32_t>(chunk_records_, sequence);
  put<uint64_t>(chunk_records_, log_time);
  put<uint64_t>(chunk_records_, publish_time);
  put_raw(chunk_records_, data, size);
  chunk_start_time_ = std::min(chunk_start_time_, log_time);
  chunk_end_time_ = std::max(chunk_end_time_, log_time);

  if (statistics_.message_count == 0) statistics_.message_start_time = statistics_.message_end_time = log_time;
  ++statistics_.message_count;
  ++statistics_.channel_message_counts[channel_id];
  statistics_.message_start_time = std::min(statistics_.message_start_time, log_time);
  statistics_.message_end_time = std::max(statistics_.message_end_time, log_time);
  if (chunk_records_.size() >= options_.chunk_size) write_chunk();
}

void McapWriter::write_chunk() {
  if (chunk_records_.empty()) return;
  const Bytes compressed = compress(options_.compression, chunk_records_);
  Bytes chunk;
  put<uint64_t>(chunk, chunk_start_time_);
  put<uint64_t>(chunk, chunk_end_time_);
  put<uint64_t>(chunk, chunk_records_.size());
  put<uint32_t>(chunk, crc32_of(chunk_records_.data(), chunk_records_.size()));
  put_string(chunk, compression_name(options_.compression));
  put<uint64_t>(chunk, compressed.size());
  put_raw(chunk, compressed.data(), compressed.size());
  Bytes record;
  put_record(record, format::kChunk, chunk);

  ChunkIndex index{chunk_start_time_, chunk_end_time_,      offset_, record.size(), {}, 0,
                   compressed.size(), chunk_records_.size()};
  for (const auto& [channel_id, entries] : chunk_message_index_) {
    Bytes content;
    put<uint16_t>(content, channel_id);
    put<uint32_t>(content, static_cast<uint32_t>(entries.size() * 16));
    for (const auto& [time, offset] : entries) {
      put<uint64_t>(content, time);
      put<uint64_t>(content, offset);
    }
    index.message_index_offsets[channel_id] = offset_ + record.size();
    put_record(record, format::kMessageIndex, content);
  }
  index.message_index_length = record.size() - index.length;
  emit(record);
  chunk_indexes_.push_back(index);
  ++statistics_.chunk_count;
  chunk_records_.clear();
  chunk_message_index_.clear();
}

void McapWriter::flush() {
  check_writable();
  write_chunk();
  if (std::fflush(file_) != 0) {
    failed_ = true;
    throw McapError(path_ + ": flush failed (" + std::strerror(errno) + ")");
  }
}

Bytes McapWriter::summary_section(uint64_t summary_start, Bytes& offsets_section) const {
  Bytes summary;
  auto group = [&](uint8_t opcode, const Bytes& records) {
    if (records.empty()) return;
    Bytes content;
    put<uint8_t>(content, opcode);
    put<uint64_t>(content, summary_start + summary.size());
    put<uint64_t>(content, records.size());
    put_record(offsets_section, format::kSummaryOffset, content);
    put_raw(summary, records.data(), records.size());
  };
  Bytes schemas, channels, statistics, chunk_indexes, metadata_indexes;
  for (const auto& schema : schemas_) {
    const Bytes record = schema_record(schema);
    put_raw(schemas, record.data(), record.size());
  }
  for (const auto& channel : channels_) {
    const Bytes record = channel_record(channel);
    put_raw(channels, record.data(), record.size());
  }
  Bytes content;
  put<uint64_t>(content, statistics_.message_count);
  put<uint16_t>(content, statistics_.schema_count);
  put<uint32_t>(content, statistics_.channel_count);
  put<uint32_t>(content, 0);  // attachments
  put<uint32_t>(content, static_cast<uint32_t>(metadata_indexes_.size()));
  put<uint32_t>(content, statistics_.chunk_count);
  put<uint64_t>(content, statistics_.message_start_time);
  put<uint64_t>(content, statistics_.message_end_time);
  put_channel_map(content, statistics_.channel_message_counts);
  put_record(statistics, format::kStatistics, content);
  for (const auto& index : chunk_indexes_) {
    Bytes record;
    put<uint64_t>(record, index.start_time);
    put<uint64_t>(record, index.end_time);
    put<uint64_t>(record, index.offset);
    put<uint64_t>(record, index.length);
    put_channel_map(record, index.message_index_offsets);
    put<uint64_t>(record, index.message_index_length);
    put_string(record, compression_name(options_.compression));
    put<uint64_t>(record, index.compressed_size);
    put<uint64_t>(record, index.uncompressed_size);
    put_record(chunk_indexes, format::kChunkIndex, record);
  }
  for (const auto& index : metadata_indexes_) {
    Bytes record;
    put<uint64_t>(record, index.offset);
    put<uint64_t>(record, index.length);
    put_string(record, index.name);
    put_record(metadata_indexes, format::kMetadataIndex, record);
  }
  group(format::kSchema, schemas);
  group(format::kChannel, channels);
  group(format::kStatistics, statistics);
  group(format::kChunkIndex, chunk_indexes);
  group(format::kMetadataIndex, metadata_indexes);
  return summary;
}

void McapWriter::close() {
  if (!file_) return;
  check_writable();
  write_chunk();
  Bytes data_end;
  Bytes content;
  put<uint32_t>(content, data_crc_);
  put_record(data_end, format::kDataEnd, content);
  emit(data_end);

  const uint64_t summary_start = offset_;
  Bytes offsets;
  Bytes tail = summary_section(summary_start, offsets);
  const uint64_t offsets_start = summary_start + tail.size();
  put_raw(tail, offsets.data(), offsets.size());
  put<uint8_t>(tail, format::kFooter);
  put<uint64_t>(tail, 8 + 8 + 4);
  put<uint64_t>(tail, summary_start);
  put<uint64_t>(tail, offsets_start);
  put<uint32_t>(tail, crc32_of(tail.data(), tail.size()));  // from the summary through the footer's offsets
  put_raw(tail, format::kMagic, sizeof(format::kMagic));
  emit(tail);
  std::FILE* file = file_;
  file_ = nullptr;
  if (std::fclose(file) != 0) throw McapError(path_ + ": close failed (" + std::strerror(errno) + ")");
}

}  // namespace scanbus::recorder

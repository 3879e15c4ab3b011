#include "scanbus/recorder/mcap_reader.hpp"

#include <cerrno>
#include <cstring>

#include "mcap_bytes.hpp"

namespace scanbus::recorder {

using namespace mcap_bytes;
namespace format = mcap_format;

namespace {

constexpr uint64_t kRecordHeader = 1 + 8;  // opcode, length
constexpr uint64_t kFooterRecord = kRecordHeader + 20;

// "chunk (0x06)": the record's name and opcode, for errors.
std::string hex(uint8_t opcode) {
  static const char* const names[] = {
      "",         "header",         "footer",         "schema",     "channel",          "message",
      "chunk",    "message index",  "chunk index",    "attachment", "attachment index", "statistics",
      "metadata", "metadata index", "summary offset", "data end"};
  char text[40];
  std::snprintf(text, sizeof(text), "%s (0x%02x)", opcode > 0 && opcode < 16 ? names[opcode] : "unknown", opcode);
  return text;
}

McapSchema parse_schema(Cursor& in) {
  McapSchema schema;
  schema.id = in.get<uint16_t>();
  schema.name = in.get_string();
  schema.encoding = in.get_string();
  schema.data = in.get_string();
  return schema;
}

McapChannel parse_channel(Cursor& in) {
  McapChannel channel;
  channel.id = in.get<uint16_t>();
  channel.schema_id = in.get<uint16_t>();
  channel.topic = in.get_string();
  channel.message_encoding = in.get_string();
  channel.metadata = in.get_string_map();
  return channel;
}

McapStatistics parse_statistics(Cursor& in) {
  McapStatistics statistics;
  statistics.message_count = in.get<uint64_t>();
  statistics.schema_count = in.get<uint16_t>();
  statistics.channel_count = in.get<uint32_t>();
  in.get<uint32_t>();  // attachments
  in.get<uint32_t>();  // metadata records
  statistics.chunk_count = in.get<uint32_t>();
  statistics.message_start_time = in.get<uint64_t>();
  statistics.message_end_time = in.get<uint64_t>();
  Cursor counts = in.get_span<uint32_t>();
  while (!counts.done()) {
    const auto channel = counts.get<uint16_t>();
    statistics.channel_message_counts[channel] = counts.get<uint64_t>();
  }
  return statistics;
}

McapChunkInfo parse_chunk_index(Cursor& in) {
  McapChunkInfo chunk;
  chunk.start_time = in.get<uint64_t>();
  chunk.end_time = in.get<uint64_t>();
  chunk.offset = in.get<uint64_t>();
  in.get<uint64_t>();       // chunk record length
  in.get_span<uint32_t>();  // message index offsets
  in.get<uint64_t>();       // message index length
  chunk.compression = in.get_string();
  chunk.compressed_size = in.get<uint64_t>();
  chunk.uncompressed_size = in.get<uint64_t>();
  return chunk;
}

}  // namespace

McapReader::McapReader(const std::string& path, uint64_t max_record) : path_(path), max_record_(max_record) {
  file_ = std::fopen(path.c_str(), "rb");
  if (!file_) throw McapError(path + ": cannot open (" + std::strerror(errno) + ")");
  try {
    open_checked();
  } catch (...) {
    std::fclose(file_);
    file_ = nullptr;
    throw;
  }
}

void McapReader::open_checked() {
  const std::string& path = path_;
  const long size = std::fseek(file_, 0, SEEK_END) == 0 ? std::ftell(file_) : -1;
  if (size < 0) throw McapError(path + ": not a regular file (cannot seek)");
  file_size_ = static_cast<uint64_t>(size);
  char magic[sizeof(format::kMagic)];
  if (file_size_ < sizeof(magic) + kRecordHeader)
    throw McapError(path + ": not an MCAP file (" + std::to_string(file_size_) + " bytes, too short)");
  read_at(0, magic, sizeof(magic), "magic");
  uint8_t header[kRecordHeader];
  read_at(sizeof(magic), header, sizeof(header), "header");
  Cursor fields(header, sizeof(header), sizeof(magic), path);
  const auto opcode = fields.get<uint8_t>();
  const auto length = fields.get<uint64_t>();
  if (std::memcmp(magic, format::kMagic, sizeof(magic)) != 0 || opcode != format::kHeader ||
      length > file_size_ - sizeof(magic) - kRecordHeader)
    throw McapError(path + ": not an MCAP file (no MCAP magic and header record at offset 0)");
  check_budget(length, path + ": the header record");
  std::vector<uint8_t> content(length);
  read_at(sizeof(magic) + kRecordHeader, content.data(), content.size(), "header");
  Cursor in(content.data(), content.size(), sizeof(magic) + kRecordHeader, path + ": header");
  profile_ = in.get_string();
  library_ = in.get_string();
  data_start_ = sizeof(magic) + kRecordHeader + length;
}

void McapReader::check_budget(uint64_t size, const std::string& what) const {
  if (size > max_record_)
    throw McapError(what + " takes " + std::to_string(size) + " bytes, more than the reader's budget of " +
                    std::to_string(max_record_) + " (--max-chunk: raise it to read this file)");
}

McapReader::~McapReader() {
  if (file_) std::fclose(file_);
}

void McapReader::read_at(uint64_t offset, void* out, size_t size, const char* what) {
  if (offset + size > file_size_ || std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0 ||
      std::fread(out, 1, size, file_) != size)
    throw McapError(path_ + ": cannot read the " + what + " at offset " + std::to_string(offset) + " (" +
                    std::to_string(size) + " bytes; the file has " + std::to_string(file_size_) + ")");
}

std::optional<McapSummary> McapReader::read_summary() {
  const uint64_t footer_at = file_size_ - sizeof(format::kMagic) - kFooterRecord;
  if (file_size_ < data_start_ + kFooterRecord + sizeof(format::kMagic)) return std::nullopt;
  std::vector<uint8_t> tail(kFooterRecord + sizeof(format::kMagic));
  read_at(footer_at, tail.data(), tail.size(), "footer");
  if (std::memcmp(tail.data() + kFooterRecord, format::kMagic, sizeof(format::kMagic)) != 0 ||
      tail[0] != format::kFooter)
    return std::nullopt;  // cut short: no footer
  Cursor footer(tail.data() + 1, kFooterRecord - 1, footer_at + 1, path_ + ": footer");
  if (footer.get<uint64_t>() != 20)
    throw McapError(path_ + ": footer at offset " + std::to_string(footer_at) + " has a wrong length");
  const auto summary_start = footer.get<uint64_t>();
  footer.get<uint64_t>();  // summary offsets: the summary is read whole
  const auto summary_crc = footer.get<uint32_t>();
  if (summary_start == 0) return std::nullopt;
  if (summary_start < data_start_ || summary_start > footer_at)
    throw McapError(path_ + ": footer at offset " + std::to_string(footer_at) + " points the summary at offset " +
                    std::to_string(summary_start) + ", outside the file's records");

  check_budget(footer_at - summary_start, path_ + ": the summary at offset " + std::to_string(summary_start));
  std::vector<uint8_t> section(footer_at - summary_start + kRecordHeader + 16);
  read_at(summary_start, section.data(), section.size(), "summary");
  if (summary_crc != 0 && crc32_of(section.data(), section.size()) != summary_crc)
    throw McapError(path_ + ": summary at offset " + std::to_string(summary_start) + " fails its CRC (corrupt)");
  McapSummary summary;
  Cursor in(section.data(), footer_at - summary_start, summary_start, path_ + ": summary");
  while (!in.done()) {
    const auto opcode = in.get<uint8_t>();
    Cursor record = in.get_span<uint64_t>();
    if (opcode == format::kSchema) {
      McapSchema schema = parse_schema(record);
      summary.schemas[schema.id] = std::move(schema);
    } else if (opcode == format::kChannel) {
      McapChannel channel = parse_channel(record);
      summary.channels[channel.id] = std::move(channel);
    } else if (opcode == format::kStatistics) {
      summary.statistics = parse_statistics(record);
    } else if (opcode == format::kChunkIndex) {
      summary.chunks.push_back(parse_chunk_index(record));
    }
  }
  return summary;
}

std::string McapReader::read_messages(const MessageHandler& on_message, bool salvage) {
  if (!salvage) {
    stream(on_message);
    return "";
  }
  try {
    stream(on_message);
  } catch (const McapError& damage) {
    return damage.what();
  }
  return "";
}

void McapReader::stream(const MessageHandler& on_message) {
  // The Data End CRC covers everything before it, magic and header included.
  std::vector<uint8_t> start(data_start_);
  read_at(0, start.data(), start.size(), "header");
  uint32_t crc = crc32_of(start.data(), start.size());
  std::vector<uint8_t> content;
  for (uint64_t offset = data_start_;;) {
    if (offset == file_size_)
      throw McapError(path_ + ": ends at offset " + std::to_string(offset) +
                      " without a Data End record (cut short: was the recording killed?)");
    if (file_size_ - offset < kRecordHeader)
      throw McapError(path_ + ": truncated record at offset " + std::to_string(offset));
    uint8_t header[kRecordHeader];
    read_at(offset, header, sizeof(header), "record header");
    Cursor fields(header, sizeof(header), offset, path_);
    const auto opcode = fields.get<uint8_t>();
    const auto length = fields.get<uint64_t>();
    if (length > file_size_ - offset - kRecordHeader)
      throw McapError(path_ + ": record " + hex(opcode) + " at offset " + std::to_string(offset) + " needs " +
                      std::to_string(length) + " bytes, the file has " +
                      std::to_string(file_size_ - offset - kRecordHeader) + " left (truncated or corrupt)");
    check_budget(length, path_ + ": record " + hex(opcode) + " at offset " + std::to_string(offset));
    content.resize(length);
    read_at(offset + kRecordHeader, content.data(), content.size(), "record");
    if (opcode == format::kDataEnd) {
      Cursor in(content.data(), content.size(), offset + kRecordHeader, path_ + ": data end");
      const auto expected = in.get<uint32_t>();
      if (expected != 0 && expected != crc)
        throw McapError(path_ + ": data section (offsets " + std::to_string(data_start_) + " to " +
                        std::to_string(offset) + ") fails the Data End CRC (corrupt)");
      return;
    }
    if (opcode == format::kFooter) return;  // no Data End record: allowed by readers of older files
    crc = crc32_of(header, sizeof(header), crc);
    crc = crc32_of(content.data(), content.size(), crc);
    handle_record(opcode, content.data(), content.size(), offset, on_message);
    offset += kRecordHeader + length;
  }
}

void McapReader::handle_record(uint8_t opcode, const uint8_t* content, size_t size, uint64_t offset,
                               const MessageHandler& on_message) {
  Cursor in(content, size, offset + kRecordHeader,
            path_ + ": record " + hex(opcode) + " at offset " + std::to_string(offset));
  if (opcode == format::kSchema) {
    McapSchema schema = parse_schema(in);
    schemas_[schema.id] = std::move(schema);
  } else if (opcode == format::kChannel) {
    McapChannel channel = parse_channel(in);
    if (channel.schema_id != 0 && !schemas_.count(channel.schema_id))
      throw McapError(path_ + ": channel '" + channel.topic + "' at offset " + std::to_string(offset) +
                      " names schema " + std::to_string(channel.schema_id) + ", which no earlier record defines");
    channels_[channel.id] = std::move(channel);
  } else if (opcode == format::kMessage) {
    McapMessage message;
    message.channel_id = in.get<uint16_t>();
    message.sequence = in.get<uint32_t>();
    message.log_time = in.get<uint64_t>();
    message.publish_time = in.get<uint64_t>();
    message.data = in.here();
    message.size = in.left();
    const auto channel = channels_.find(message.channel_id);
    if (channel == channels_.end())
      throw McapError(path_ + ": message at offset " + std::to_string(offset) + " is on channel " +
                      std::to_string(message.channel_id) + ", which no earlier record defines");
    on_message(message, channel->second);
  } else if (opcode == format::kChunk) {
    handle_chunk(content, size, offset, on_message);
  } else if (opcode == format::kMetadata) {
    std::string name = in.get_string();
    metadata_[std::move(name)] = in.get_string_map();
  }
  // Other records (indexes, attachments) carry no messages; unknown opcodes are
  // skipped, as the spec asks of readers.
}

void McapReader::handle_chunk(const uint8_t* content, size_t size, uint64_t offset, const MessageHandler& on_message) {
  const std::string what = path_ + ": chunk at offset " + std::to_string(offset);
  Cursor in(content, size, offset + kRecordHeader, what);
  in.get<uint64_t>();  // message start time
  in.get<uint64_t>();  // message end time
  const auto uncompressed_size = in.get<uint64_t>();
  const auto uncompressed_crc = in.get<uint32_t>();
  const std::string compression = in.get_string();
  Cursor records = in.get_span<uint64_t>();
  check_budget(uncompressed_size, what + " uncompressed");
  const Bytes plain = decompress(compression, records.here(), records.left(), uncompressed_size, what);
  if (uncompressed_crc != 0 && crc32_of(plain.data(), plain.size()) != uncompressed_crc)
    throw McapError(what + " fails its CRC (corrupt)");
  // Offsets inside a chunk are of its uncompressed records; errors name the chunk.
  Cursor inner(plain.data(), plain.size(), 0, what + ", uncompressed record");
  while (!inner.done()) {
    const auto opcode = inner.get<uint8_t>();
    Cursor record = inner.get_span<uint64_t>();
    if (opcode != format::kSchema && opcode != format::kChannel && opcode != format::kMessage)
      throw McapError(what + " holds a " + hex(opcode) +
                      " record (only schemas, channels and messages belong in chunks)");
    handle_record(opcode, record.here(), record.left(), offset, on_message);
  }
}

}  // namespace scanbus::recorder

// Little-endian field encoding and decoding of MCAP records, and chunk compression.
// Private to the MCAP writer and reader.
#pragma once

#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "scanbus/recorder/mcap.hpp"

namespace scanbus::recorder::mcap_bytes {

using Bytes = std::vector<uint8_t>;

template <class T>
void put(Bytes& out, T value) {
  static_assert(std::is_integral_v<T>);
  for (size_t i = 0; i < sizeof(T); ++i) out.push_back(static_cast<uint8_t>(static_cast<uint64_t>(value) >> (8 * i)));
}
inline void put_raw(Bytes& out, const void* data, size_t size) {
  const auto* bytes = static_cast<const uint8_t*>(data);
  out.insert(out.end(), bytes, bytes + size);
}
inline void put_string(Bytes& out, const std::string& text) {
  put<uint32_t>(out, static_cast<uint32_t>(text.size()));
  put_raw(out, text.data(), text.size());
}
inline void put_string_map(Bytes& out, const std::map<std::string, std::string>& map) {
  Bytes entries;
  for (const auto& [key, value] : map) {
    put_string(entries, key);
    put_string(entries, value);
  }
  put<uint32_t>(out, static_cast<uint32_t>(entries.size()));
  put_raw(out, entries.data(), entries.size());
}
// Map<uint16, uint64> (channel counts, message index offsets): byte length, then pairs.
inline void put_channel_map(Bytes& out, const std::map<uint16_t, uint64_t>& map) {
  put<uint32_t>(out, static_cast<uint32_t>(map.size() * (2 + 8)));
  for (const auto& [channel_id, value] : map) {
    put<uint16_t>(out, channel_id);
    put<uint64_t>(out, value);
  }
}
// Opcode, length, content.
inline void put_record(Bytes& out, uint8_t opcode, const Bytes& content) {
  put<uint8_t>(out, opcode);
  put<uint64_t>(out, content.size());
  put_raw(out, content.data(), content.size());
}

// Reads fields from a bounded span; running past its end throws McapError naming the
// absolute file offset of the field (`base` is the span's offset in the file).
class Cursor {
 public:
  Cursor(const uint8_t* data, size_t size, uint64_t base, std::string what)
      : data_(data), size_(size), base_(base), what_(std::move(what)) {}

  template <class T>
  T get() {
    need(sizeof(T));
    uint64_t value = 0;
    for (size_t i = 0; i < sizeof(T); ++i) value |= static_cast<uint64_t>(data_[position_ + i]) << (8 * i);
    position_ += sizeof(T);
    return static_cast<T>(value);
  }
  std::string get_string() {
    const auto size = get<uint32_t>();
    need(size);
    std::string text(reinterpret_cast<const char*>(data_ + position_), size);
    position_ += size;
    return text;
  }
  std::map<std::string, std::string> get_string_map() {
    const auto size = get<uint32_t>();
    need(size);
    Cursor entries(data_ + position_, size, offset(), what_);
    position_ += size;
    std::map<std::string, std::string> map;
    while (!entries.done()) {
      std::string key = entries.get_string();
      map[std::move(key)] = entries.get_string();
    }
    return map;
  }
  // A u32- or u64-length-prefixed byte field, returned as a sub-cursor.
  template <class Length>
  Cursor get_span() {
    const auto size = static_cast<uint64_t>(get<Length>());
    need(size);
    Cursor span(data_ + position_, static_cast<size_t>(size), offset(), what_);
    position_ += static_cast<size_t>(size);
    return span;
  }
  const uint8_t* here() const { return data_ + position_; }
  size_t left() const { return size_ - position_; }
  bool done() const { return position_ >= size_; }
  uint64_t offset() const { return base_ + position_; }
  void skip(uint64_t size) {
    need(size);
    position_ += static_cast<size_t>(size);
  }

 private:
  void need(uint64_t size) const {
    if (size > size_ - position_)
      throw McapError(what_ + ": truncated field at offset " + std::to_string(offset()) + " (needs " +
                      std::to_string(size) + " bytes, " + std::to_string(size_ - position_) + " left)");
  }
  const uint8_t* data_;
  size_t size_;
  size_t position_ = 0;
  uint64_t base_;
  std::string what_;
};

uint32_t crc32_of(const uint8_t* data, size_t size, uint32_t crc = 0);
Bytes compress(Compression compression, const Bytes& records);
// Throws McapError (naming `what`) when the data does not decompress to `uncompressed_size`.
Bytes decompress(const std::string& compression, const uint8_t* data, size_t size, uint64_t uncompressed_size,
                 const std::string& what);

}  // namespace scanbus::recorder::mcap_bytes

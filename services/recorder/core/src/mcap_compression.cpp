// Chunk compression with the spec's two codecs: zstd frames and LZ4 frames (not raw LZ4
// blocks), and the CRC-32 (zlib's) that guards chunks and the file's sections.
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <memory>

#include "mcap_bytes.hpp"

namespace scanbus::recorder {

std::string compression_name(Compression compression) {
  switch (compression) {
    case Compression::Lz4:
      return "lz4";
    case Compression::Zstd:
      return "zstd";
    case Compression::None:
      break;
  }
  return "";
}

Compression compression_from_name(const std::string& name) {
  if (name == "zstd") return Compression::Zstd;
  if (name == "lz4") return Compression::Lz4;
  if (name.empty() || name == "none") return Compression::None;
  throw McapError("unknown MCAP chunk compression '" + name + "' (zstd, lz4 or none)");
}

namespace mcap_bytes {

uint32_t crc32_of(const uint8_t* data, size_t size, uint32_t crc) {
  // zlib takes uInt lengths: feed large buffers in pieces.
  while (size > 0) {
    const auto piece = static_cast<uInt>(std::min<size_t>(size, 1u << 30));
    crc = static_cast<uint32_t>(::crc32(crc, data, piece));
    data += piece;
    size -= piece;
  }
  return crc;
}

Bytes compress(Compression compression, const Bytes& records) {
  Bytes out;
  if (compression == Compression::Zstd) {
    out.resize(ZSTD_compressBound(records.size()));
    // Level 1: recording must keep up with the sensors; higher levels gain little on
    // noisy floats (docs/performance.md, recording).
    const size_t size = ZSTD_compress(out.data(), out.size(), records.data(), records.size(), 1);
    if (ZSTD_isError(size)) throw McapError(std::string("zstd compression failed: ") + ZSTD_getErrorName(size));
    out.resize(size);
  } else if (compression == Compression::Lz4) {
    LZ4F_preferences_t preferences{};
    preferences.frameInfo.contentSize = records.size();
    out.resize(LZ4F_compressFrameBound(records.size(), &preferences));
    const size_t size = LZ4F_compressFrame(out.data(), out.size(), records.data(), records.size(), &preferences);
    if (LZ4F_isError(size)) throw McapError(std::string("lz4 compression failed: ") + LZ4F_getErrorName(size));
    out.resize(size);
  } else {
    out = records;
  }
  return out;
}

namespace {

// Decompressed bytes land here. The buffer grows with what the data really gives, never
// straight to the size a (possibly corrupt) chunk claims, and never past that size.
class GrowingOutput {
 public:
  GrowingOutput(uint64_t limit, size_t compressed_size, const std::string& what) : limit_(limit), what_(what) {
    out_.resize(static_cast<size_t>(std::min<uint64_t>(limit, std::max<uint64_t>(1 << 20, 8ull * compressed_size))));
  }
  // Room after `written`, growing when full; throws when the data outgrows the limit.
  size_t room(size_t written) {
    if (written == out_.size()) {
      if (out_.size() >= limit_)
        throw McapError(what_ + ": the data gives more than the " + std::to_string(limit_) + " bytes the chunk says");
      out_.resize(static_cast<size_t>(std::min<uint64_t>(limit_, 2ull * out_.size())));
    }
    return out_.size() - written;
  }
  uint8_t* at(size_t written) { return out_.data() + written; }
  Bytes finish(size_t written) {
    if (written != limit_)
      throw McapError(what_ + ": the data gives " + std::to_string(written) + " bytes, the chunk says " +
                      std::to_string(limit_));
    out_.resize(written);
    return std::move(out_);
  }

 private:
  Bytes out_;
  uint64_t limit_;
  std::string what_;
};

Bytes decompress_lz4(const uint8_t* data, size_t size, uint64_t uncompressed_size, const std::string& what) {
  GrowingOutput out(uncompressed_size, size, what);
  std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> context(nullptr, LZ4F_freeDecompressionContext);
  LZ4F_dctx* created = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&created, LZ4F_VERSION)))
    throw McapError(what + ": cannot create an lz4 decompression context");
  context.reset(created);
  size_t written = 0, read = 0, status = 1;
  while (read < size || status != 0) {
    size_t out_size = out.room(written);
    size_t in_size = size - read;
    status = LZ4F_decompress(context.get(), out.at(written), &out_size, data + read, &in_size, nullptr);
    if (LZ4F_isError(status)) throw McapError(what + ": lz4 data is corrupt (" + LZ4F_getErrorName(status) + ")");
    written += out_size;
    read += in_size;
    if (out_size == 0 && in_size == 0) break;  // input used up mid-frame: finish() reports the shortfall
  }
  return out.finish(written);
}

Bytes decompress_zstd(const uint8_t* data, size_t size, uint64_t uncompressed_size, const std::string& what) {
  GrowingOutput out(uncompressed_size, size, what);
  std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> context(ZSTD_createDCtx(), ZSTD_freeDCtx);
  if (!context) throw McapError(what + ": cannot create a zstd decompression context");
  ZSTD_inBuffer in{data, size, 0};
  size_t written = 0, status = 1;
  while (in.pos < in.size || status != 0) {
    const size_t room = out.room(written);  // may move the buffer: before taking its address
    ZSTD_outBuffer buffer{out.at(0), written + room, written};
    const size_t before_in = in.pos;
    status = ZSTD_decompressStream(context.get(), &buffer, &in);
    if (ZSTD_isError(status)) throw McapError(what + ": zstd data is corrupt (" + ZSTD_getErrorName(status) + ")");
    const bool progressed = buffer.pos > written || in.pos > before_in;
    written = buffer.pos;
    if (!progressed) break;  // input used up mid-frame: finish() reports the shortfall
  }
  return out.finish(written);
}

}  // namespace

Bytes decompress(const std::string& compression, const uint8_t* data, size_t size, uint64_t uncompressed_size,
                 const std::string& what) {
  if (compression.empty()) {
    if (size != uncompressed_size)
      throw McapError(what + ": uncompressed chunk of " + std::to_string(size) + " bytes, the chunk says " +
                      std::to_string(uncompressed_size));
    return Bytes(data, data + size);
  }
  try {
    if (compression == "lz4") return decompress_lz4(data, size, uncompressed_size, what);
    if (compression == "zstd") return decompress_zstd(data, size, uncompressed_size, what);
  } catch (const std::bad_alloc&) {
    throw McapError(what + ": no memory for its " + std::to_string(uncompressed_size) + " uncompressed bytes");
  }
  throw McapError(what + ": unsupported chunk compression '" + compression + "'");
}

}  // namespace mcap_bytes
}  // namespace scanbus::recorder

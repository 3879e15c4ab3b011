// Chunk compression with the spec's two codecs: zstd frames and LZ4 frames (not raw LZ4
// blocks), and the CRC-32 (zlib's) that guards chunks and the file's sections.
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include "mcap_bytes.hpp"

namespace scanbus::recorder {

std::string compression_name(Compression compression) {
  switch (compression) {
    case Compression::Lz4: return "lz4";
    case Compression::Zstd: return "zstd";
    case Compression::None: break;
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

Bytes decompress_lz4(const uint8_t* data, size_t size, uint64_t uncompressed_size, const std::string& what) {
  Bytes out(uncompressed_size);
  LZ4F_dctx* context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION)))
    throw McapError(what + ": cannot create an lz4 decompression context");
  size_t written = 0;
  size_t read = 0;
  size_t status = 1;
  while (status != 0 && read < size) {
    size_t out_size = out.size() - written;
    size_t in_size = size - read;
    status = LZ4F_decompress(context, out.data() + written, &out_size, data + read, &in_size, nullptr);
    if (LZ4F_isError(status)) {
      LZ4F_freeDecompressionContext(context);
      throw McapError(what + ": lz4 data is corrupt (" + LZ4F_getErrorName(status) + ")");
    }
    written += out_size;
    read += in_size;
    if (out_size == 0 && in_size == 0) break;
  }
  LZ4F_freeDecompressionContext(context);
  if (status != 0 || written != uncompressed_size)
    throw McapError(what + ": lz4 data gives " + std::to_string(written) + " bytes, the chunk says " +
                    std::to_string(uncompressed_size));
  return out;
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
  if (compression == "lz4") return decompress_lz4(data, size, uncompressed_size, what);
  if (compression != "zstd") throw McapError(what + ": unsupported chunk compression '" + compression + "'");
  Bytes out(uncompressed_size);
  const size_t result = ZSTD_decompress(out.data(), out.size(), data, size);
  if (ZSTD_isError(result)) throw McapError(what + ": zstd data is corrupt (" + ZSTD_getErrorName(result) + ")");
  if (result != uncompressed_size)
    throw McapError(what + ": zstd data gives " + std::to_string(result) + " bytes, the chunk says " +
                    std::to_string(uncompressed_size));
  return out;
}

}  // namespace mcap_bytes
}  // namespace scanbus::recorder

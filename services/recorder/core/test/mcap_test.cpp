#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "scanbus/recorder/mcap_reader.hpp"
#include "scanbus/recorder/mcap_writer.hpp"

namespace scanbus::recorder {
namespace {

namespace fs = std::filesystem;

struct Sample {
  uint16_t channel;
  uint32_t sequence;
  uint64_t log_time, publish_time;
  std::vector<uint8_t> data;
};

std::vector<Sample> samples(size_t count, size_t largest) {
  std::mt19937 random(7);
  std::vector<Sample> out;
  for (size_t i = 0; i < count; ++i) {
    Sample sample{static_cast<uint16_t>(1 + i % 2),
                  static_cast<uint32_t>(i),
                  1'000'000'000ull + i * 1000,
                  1'000'000'000ull + i * 1000 - 7,
                  {}};
    sample.data.resize(random() % largest);
    for (auto& byte : sample.data) byte = static_cast<uint8_t>(random() % 16);  // compressible
    out.push_back(std::move(sample));
  }
  return out;
}

fs::path temporary(const std::string& name) {
  return fs::temp_directory_path() / ("scanbus_mcap_" + std::to_string(::getpid()) + "_" + name);
}

// Writes the samples on two channels; with `close` false the file is left as a killed
// recorder leaves it after its last flush.
void write_file(const fs::path& path, const std::vector<Sample>& all, McapWriterOptions options, bool close = true) {
  McapWriter writer(path.string(), options);
  const uint16_t schema = writer.add_schema("std_msgs/msg/String", "ros2msg", "string data\n");
  writer.add_channel(schema, "/one", "cdr", {{"offered_qos_profiles", ""}});
  writer.add_channel(schema, "/two", "cdr", {});
  writer.add_metadata("flight", {{"scenario", "4"}, {"origin", "52.5 13.4 34"}});
  for (const auto& s : all)
    writer.write(s.channel, s.sequence, s.log_time, s.publish_time, s.data.data(), s.data.size());
  if (close) {
    writer.close();
  } else {
    writer.flush();
    std::FILE* copy = std::fopen((path.string() + ".killed").c_str(), "wb");
    const auto bytes = [&] {
      std::ifstream in(path, std::ios::binary);
      return std::vector<char>(std::istreambuf_iterator<char>(in), {});
    }();
    std::fwrite(bytes.data(), 1, bytes.size(), copy);
    std::fclose(copy);
  }
}

std::vector<Sample> read_all(const fs::path& path, bool salvage, std::string* damage = nullptr) {
  McapReader reader(path.string());
  std::vector<Sample> out;
  const std::string found = reader.read_messages(
      [&](const McapMessage& m, const McapChannel& channel) {
        EXPECT_EQ(channel.id, m.channel_id);
        out.push_back({m.channel_id, m.sequence, m.log_time, m.publish_time, {m.data, m.data + m.size}});
      },
      salvage);
  if (damage) *damage = found;
  return out;
}

void expect_equal(const std::vector<Sample>& expected, const std::vector<Sample>& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(expected[i].channel, actual[i].channel) << i;
    EXPECT_EQ(expected[i].sequence, actual[i].sequence) << i;
    EXPECT_EQ(expected[i].log_time, actual[i].log_time) << i;
    EXPECT_EQ(expected[i].publish_time, actual[i].publish_time) << i;
    EXPECT_EQ(expected[i].data, actual[i].data) << i;
  }
}

void truncate_copy(const fs::path& from, const fs::path& to, size_t size) {
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  fs::resize_file(to, size);
}

class McapRoundTrip : public ::testing::TestWithParam<Compression> {};

TEST_P(McapRoundTrip, MessagesSchemasAndSummaryReadBackExactly) {
  const auto path = temporary("round_trip.mcap");
  // A 200 kB message outgrows the 64 kB chunks: it gets a chunk of its own.
  auto all = samples(500, 2000);
  all[100].data.assign(200'000, 3);
  write_file(path, all, {GetParam(), 64 << 10});

  McapReader reader(path.string());
  EXPECT_EQ(reader.profile(), "ros2");
  const auto summary = reader.read_summary();
  ASSERT_TRUE(summary);
  ASSERT_TRUE(summary->statistics);
  EXPECT_EQ(summary->statistics->message_count, 500u);
  EXPECT_EQ(summary->statistics->channel_message_counts.at(1), 250u);
  EXPECT_EQ(summary->statistics->channel_message_counts.at(2), 250u);
  EXPECT_EQ(summary->statistics->message_start_time, all.front().log_time);
  EXPECT_EQ(summary->statistics->message_end_time, all.back().log_time);
  EXPECT_GE(summary->chunks.size(), 3u);
  EXPECT_EQ(summary->statistics->chunk_count, summary->chunks.size());
  EXPECT_EQ(summary->channels.at(1).topic, "/one");
  EXPECT_EQ(summary->channels.at(1).metadata.count("offered_qos_profiles"), 1u);
  EXPECT_EQ(summary->schemas.at(1).data, "string data\n");
  for (const auto& chunk : summary->chunks) EXPECT_EQ(chunk.compression, compression_name(GetParam()));

  expect_equal(all, read_all(path, false));
  McapReader streamed(path.string());
  streamed.read_messages([](const McapMessage&, const McapChannel&) {});
  EXPECT_EQ(streamed.metadata().at("flight").at("origin"), "52.5 13.4 34");
  fs::remove(path);
}

INSTANTIATE_TEST_SUITE_P(Compressions, McapRoundTrip,
                         ::testing::Values(Compression::None, Compression::Lz4, Compression::Zstd));

TEST(Mcap, KilledRecordingKeepsEveryFlushedChunk) {
  const auto path = temporary("killed.mcap");
  const auto all = samples(300, 500);
  write_file(path, all, {Compression::Zstd, 16 << 10}, false);
  const fs::path killed = path.string() + ".killed";

  try {
    read_all(killed, false);
    FAIL() << "a file without Data End and footer must be rejected";
  } catch (const McapError& error) {
    EXPECT_NE(std::string(error.what()).find("without a Data End record"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("offset " + std::to_string(fs::file_size(killed))), std::string::npos);
  }
  std::string damage;
  expect_equal(all, read_all(killed, true, &damage));
  EXPECT_FALSE(damage.empty());
  EXPECT_FALSE(McapReader(killed.string()).read_summary());
  fs::remove(path);
  fs::remove(killed);
}

TEST(Mcap, TruncatedInsideAChunkNamesItsOffsetAndSalvagesTheChunksBefore) {
  const auto path = temporary("truncated.mcap");
  const auto all = samples(300, 500);
  write_file(path, all, {Compression::Lz4, 16 << 10});
  McapReader reader(path.string());
  const auto chunks = reader.read_summary()->chunks;
  ASSERT_GE(chunks.size(), 3u);
  const auto cut = temporary("truncated_cut.mcap");
  truncate_copy(path, cut, chunks[2].offset + 100);

  try {
    read_all(cut, false);
    FAIL() << "a truncated chunk must be rejected";
  } catch (const McapError& error) {
    EXPECT_NE(std::string(error.what()).find("at offset " + std::to_string(chunks[2].offset)), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("truncated"), std::string::npos) << error.what();
  }
  std::string damage;
  const auto salvaged = read_all(cut, true, &damage);
  EXPECT_NE(damage.find(std::to_string(chunks[2].offset)), std::string::npos);
  ASSERT_FALSE(salvaged.empty());
  EXPECT_EQ(salvaged.back().log_time, chunks[1].end_time);  // everything of the two whole chunks
  expect_equal(std::vector<Sample>(all.begin(), all.begin() + salvaged.size()), salvaged);
  fs::remove(path);
  fs::remove(cut);
}

TEST(Mcap, CorruptChunkFailsItsCrcAndSalvageStopsBeforeIt) {
  const auto path = temporary("corrupt.mcap");
  const auto all = samples(300, 500);
  write_file(path, all, {Compression::None, 16 << 10});
  const auto chunks = McapReader(path.string()).read_summary()->chunks;
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(chunks[1].offset + 200));
    file.put('\x55');
  }
  try {
    read_all(path, false);
    FAIL() << "a corrupt chunk must be rejected";
  } catch (const McapError& error) {
    EXPECT_NE(std::string(error.what()).find("chunk at offset " + std::to_string(chunks[1].offset)), std::string::npos)
        << error.what();
  }
  std::string damage;
  const auto salvaged = read_all(path, true, &damage);
  EXPECT_NE(damage.find("CRC"), std::string::npos) << damage;
  ASSERT_FALSE(salvaged.empty());
  EXPECT_EQ(salvaged.back().log_time, chunks[0].end_time);
  fs::remove(path);
}

// Every prefix of a file (a recording cut at any byte): an McapError or a salvaged prefix of
// the messages, never a crash, a hang or a wrong message.
TEST(Mcap, EveryTruncationIsAnErrorOrAPrefix) {
  const auto path = temporary("prefixes.mcap");
  const auto all = samples(40, 100);
  write_file(path, all, {Compression::Zstd, 1 << 10});
  const auto cut = temporary("prefixes_cut.mcap");
  const size_t size = fs::file_size(path);
  for (size_t length = 0; length < size; ++length) {
    truncate_copy(path, cut, length);
    try {
      std::string damage;
      const auto salvaged = read_all(cut, true, &damage);
      expect_equal(std::vector<Sample>(all.begin(), all.begin() + std::min(salvaged.size(), all.size())), salvaged);
      if (damage.empty()) {
        EXPECT_EQ(salvaged.size(), all.size()) << "a clean read of a cut file at " << length;
      }
    } catch (const McapError&) {
      EXPECT_LT(length, 36u) << "only a file too short for its header may be refused outright";
    }
  }
  fs::remove(path);
  fs::remove(cut);
}

// Every byte of a small file flipped in turn (a corrupt disk, a fuzzer's first pass): the
// reader either reads on or names the damage; never another exception, a crash or a hang.
class McapCorruption : public ::testing::TestWithParam<Compression> {};

TEST_P(McapCorruption, EveryFlippedByteIsReadOrNamed) {
  const auto path = temporary("flipped.mcap");
  const auto all = samples(20, 60);
  write_file(path, all, {GetParam(), 512});
  std::vector<char> bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const auto flipped = temporary("flipped_copy.mcap");
  size_t named = 0;
  for (size_t at = 0; at < bytes.size(); ++at) {
    auto copy = bytes;
    copy[at] = static_cast<char>(~copy[at]);
    std::ofstream(flipped, std::ios::binary | std::ios::trunc)
        .write(copy.data(), static_cast<std::streamsize>(copy.size()));
    try {
      McapReader reader(flipped.string());
      reader.read_summary();
      std::string damage;
      read_all(flipped, true, &damage);
      named += !damage.empty();
    } catch (const McapError&) {
      ++named;
    }
  }
  EXPECT_GT(named, bytes.size() / 2) << "most flips must be noticed (CRCs, lengths)";
  fs::remove(path);
  fs::remove(flipped);
}

INSTANTIATE_TEST_SUITE_P(Compressions, McapCorruption,
                         ::testing::Values(Compression::None, Compression::Lz4, Compression::Zstd));

// A chunk that claims 15 GiB of records: refused without reserving them.
TEST(Mcap, ChunkClaimingHugeSizeIsRefusedWithoutAllocatingIt) {
  const auto path = temporary("huge.mcap");
  write_file(path, samples(10, 50), {Compression::Zstd, 1 << 20});
  const auto chunk = McapReader(path.string()).read_summary()->chunks.at(0);
  {
    // Chunk record: opcode, length, start time, end time, then uncompressed_size.
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(chunk.offset + 9 + 16));
    const uint64_t huge = 15ull << 30;
    for (int i = 0; i < 8; ++i) file.put(static_cast<char>(huge >> (8 * i)));
  }
  try {
    read_all(path, false);
    FAIL();
  } catch (const McapError& error) {
    EXPECT_NE(std::string(error.what()).find("chunk at offset " + std::to_string(chunk.offset)), std::string::npos)
        << error.what();
  }
  fs::remove(path);
}

TEST(Mcap, RejectsAFileThatIsNotMcap) {
  const auto path = temporary("not.mcap");
  std::ofstream(path) << "# a PCD file, say\nVERSION 0.7\nFIELDS x y z\n";
  try {
    McapReader reader(path.string());
    FAIL();
  } catch (const McapError& error) {
    EXPECT_NE(std::string(error.what()).find("not an MCAP file"), std::string::npos) << error.what();
  }
  fs::remove(path);
  EXPECT_THROW(McapReader("/nonexistent/file.mcap"), McapError);
}

TEST(Mcap, UnknownCompressionNameIsRefused) {
  EXPECT_EQ(compression_from_name("none"), Compression::None);
  EXPECT_EQ(compression_from_name("lz4"), Compression::Lz4);
  EXPECT_THROW(compression_from_name("gzip"), McapError);
}

}  // namespace
}  // namespace scanbus::recorder

namespace scanbus::recorder {

// zstd and lz4 expand legitimately: a chunk of 1 MiB of zeros is a few hundred bytes on
// disk. Over the reader's memory budget it is refused before it is inflated, naming the
// chunk's offset and both sizes; a larger budget reads it.
TEST(Mcap, AChunkOverTheMemoryBudgetIsRefusedNamingItsSize) {
  const auto path = temporary("budget.mcap");
  std::vector<Sample> zeros;
  for (uint32_t i = 0; i < 4; ++i)
    zeros.push_back({1, i, 1'000'000'000ull + i, 1'000'000'000ull + i, std::vector<uint8_t>(256 << 10)});
  write_file(path, zeros, {Compression::Zstd, 4 << 20});
  const auto chunks = McapReader(path.string()).read_summary()->chunks;
  ASSERT_EQ(chunks.size(), 1u);
  ASSERT_LT(chunks[0].compressed_size, 64u << 10);
  try {
    McapReader(path.string(), 512 << 10).read_messages([](const McapMessage&, const McapChannel&) {});
    FAIL() << "a 1 MiB chunk read with a 512 KiB budget";
  } catch (const McapError& error) {
    const std::string what = error.what();
    EXPECT_NE(
        what.find("chunk at offset " + std::to_string(chunks[0].offset) + " uncompressed takes " +
                  std::to_string(chunks[0].uncompressed_size) + " bytes, more than the reader's budget of 524288"),
        std::string::npos)
        << what;
  }
  size_t messages = 0;
  McapReader(path.string(), 2 << 20).read_messages([&](const McapMessage&, const McapChannel&) { ++messages; });
  EXPECT_EQ(messages, 4u);
  fs::remove(path);
}

// A chunk claiming 16 GiB is refused by the default budget (1 GiB), nothing allocated.
TEST(Mcap, AChunkClaimingGigabytesIsRefusedByTheDefaultBudget) {
  const auto path = temporary("claims.mcap");
  write_file(path, samples(50, 100), {Compression::Lz4, 1 << 20});
  const auto chunk = McapReader(path.string()).read_summary()->chunks.at(0);
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(chunk.offset + 1 + 8 + 16));  // opcode, length, start and end time
    const uint64_t claimed = uint64_t{16} << 30;
    file.write(reinterpret_cast<const char*>(&claimed), sizeof(claimed));
  }
  try {
    read_all(path, false);
    FAIL() << "a chunk claiming 16 GiB was read";
  } catch (const McapError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("uncompressed takes 17179869184 bytes, more than the reader's budget of 1073741824"),
              std::string::npos)
        << error.what();
  }
  fs::remove(path);
}

}  // namespace scanbus::recorder

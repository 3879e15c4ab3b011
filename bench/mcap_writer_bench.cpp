// The MCAP writer alone: MB/s of 1,000,000-point clouds (16 MB messages) into a file with
// each chunk compression, and the compressed share. The recording service adds DDS on top
// (bench/recording_throughput.sh measures the two together).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "room_cloud.hpp"
#include "scanbus/recorder/mcap_writer.hpp"

namespace scanbus::recorder {
namespace {

void BM_McapWriterCloud(benchmark::State& state) {
  const auto compression = static_cast<Compression>(state.range(0));
  const std::vector<uint8_t> clouds[2] = {bench::room_cloud_points(1'000'000, 1),
                                          bench::room_cloud_points(1'000'000, 2)};
  const auto path = std::filesystem::temp_directory_path() / "scanbus_mcap_writer_bench.mcap";
  McapWriter writer(path.string(), {compression, 4 << 20});
  const uint16_t schema = writer.add_schema("sensor_msgs/msg/PointCloud2", "ros2msg", "");
  const uint16_t channel = writer.add_channel(schema, "/scanner/cloud", "cdr", {});
  uint32_t sequence = 0;
  for (auto _ : state) {
    const auto& cloud = clouds[sequence % 2];
    writer.write(channel, sequence, sequence, sequence, cloud.data(), cloud.size());
    ++sequence;
  }
  writer.close();
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * clouds[0].size()));
  state.counters["file_share"] = static_cast<double>(std::filesystem::file_size(path)) /
                                 static_cast<double>(state.iterations() * clouds[0].size());
  std::filesystem::remove(path);
}
BENCHMARK(BM_McapWriterCloud)
    ->ArgName("compression")
    ->Arg(static_cast<int>(Compression::None))
    ->Arg(static_cast<int>(Compression::Lz4))
    ->Arg(static_cast<int>(Compression::Zstd))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace scanbus::recorder

BENCHMARK_MAIN();

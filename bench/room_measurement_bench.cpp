// Room measurement end to end (filter, VoxelGrid, RANSAC, walls, polygon, floor and
// ceiling) on simulated scans of the thesis's case 1 room, on one core.
// Targets (issue 4): 18,500 points under 20 ms, 1,000,000 points under 1 s.
#include <benchmark/benchmark.h>

#include <stdexcept>

#include "scanbus/room_evaluation/simulated_scan.hpp"
#include "scanbus/room_measurement/room_measurement.hpp"
#include "scanbus/sim/room_file.hpp"

namespace {

using namespace scanbus;

// Interleaved full scans at 12 RPM (about 6,500 points each) until `count` points.
const std::vector<Eigen::Vector3f>& scan_of(size_t count) {
  static std::map<size_t, std::vector<Eigen::Vector3f>> scans;
  auto& points = scans[count];
  if (points.empty()) {
    const auto room = sim::load_room_file(std::string(SCANBUS_SOURCE_DIR) + "/config/rooms/thesis_case1.yaml");
    room_evaluation::SimulatedScanSettings settings;
    settings.cycles = static_cast<int>(count / 6000 + 1);
    points = room_evaluation::simulated_scan(room, settings);
    if (points.size() < count) throw std::runtime_error("simulated scan too small");
    points.resize(count);
  }
  return points;
}

void MeasureRoom(benchmark::State& state) {
  const auto& points = scan_of(static_cast<size_t>(state.range(0)));
  room_measurement::RoomResult result;
  for (auto _ : state) {
    result = room_measurement::measure_room(points, room_measurement::RoomSettings{});
    benchmark::DoNotOptimize(result);
  }
  if (result.status != room_measurement::RoomStatus::Ok) state.SkipWithError(result.message.c_str());
  state.counters["walls"] = static_cast<double>(result.walls.size());
  state.counters["area_m2"] = result.area;
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

BENCHMARK(MeasureRoom)->Arg(18500)->Arg(1000000)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

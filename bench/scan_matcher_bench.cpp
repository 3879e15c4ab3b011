// PL-ICP scan matching per scan (ScanMatcher::add_scan: range gating, correspondence search,
// Gauss-Newton, the local map) on one core. Target (issues 5 and 20): 2,000 scans per second
// for 361-ray scans, with the local map. Two inputs: a synthetic room flight (always there)
// and the real MIT CSAIL log of the Freiburg benchmark (skipped when ../shared is absent).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>

#include "laser_world.hpp"
#include "scanbus/scan_matcher/laser_log.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"

namespace {

using namespace scanbus;
using scan_matcher::Pose2;

std::vector<sensor::LaserScan> room_flight() {
  const auto world = test_support::LaserWorld::room();
  std::mt19937 random(3);
  std::vector<sensor::LaserScan> scans;
  Pose2 pose{-1.5, -0.5, 0.2};
  for (int i = 0; i < 200; ++i) {
    scans.push_back(world.scan(pose, {}, random));
    pose = pose * Pose2{0.02, 0.0, (i % 100 < 50 ? 1.0 : -1.0) * M_PI / 180};
  }
  return scans;
}

std::vector<sensor::LaserScan> mit_csail() {
  const std::string path = std::string(SCANBUS_SOURCE_DIR) + "/../shared/data/freiburg/mit-csail.clf";
  std::vector<sensor::LaserScan> scans;
  if (!std::filesystem::exists(path)) return scans;
  for (const auto& record : scan_matcher::read_carmen_log(path)) scans.push_back(record.scan);
  return scans;
}

// Matches all the scans in order with a new matcher, once per iteration (the whole log, not
// the first second of it: the map grows and the scene changes along it); the map holds
// `map_keyframes` keyframes (1: pairwise), the other settings the defaults.
void match(benchmark::State& state, const std::vector<sensor::LaserScan>& scans, int map_keyframes) {
  if (scans.empty()) {
    state.SkipWithError("../shared/data/freiburg/mit-csail.clf not found");
    return;
  }
  scan_matcher::MatcherSettings settings;
  settings.map_keyframes = map_keyframes;
  size_t failed = 0, map_points = 0;
  for (auto _ : state) {
    scan_matcher::ScanMatcher matcher(settings);
    failed = map_points = 0;
    for (size_t i = 0; i < scans.size(); ++i) {
      const auto result = matcher.add_scan(scans[i]);
      failed += i > 0 && result.quality != scan_matcher::MatchQuality::Ok;
      map_points = std::max(map_points, matcher.map_points());
    }
  }
  // items per second = scans per second; seconds_per_scan its inverse
  const auto scans_matched = static_cast<int64_t>(state.iterations() * scans.size());
  state.SetItemsProcessed(scans_matched);
  state.counters["seconds_per_scan"] =
      benchmark::Counter(static_cast<double>(scans_matched), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["rays"] = static_cast<double>(scans.front().ranges.size());
  state.counters["failed"] = static_cast<double>(failed);          // in one pass
  state.counters["map_points"] = static_cast<double>(map_points);  // the most the map held
}

void MatchRoomFlight(benchmark::State& state) {
  static const auto scans = room_flight();
  match(state, scans, static_cast<int>(state.range(0)));
}

void MatchMitCsail(benchmark::State& state) {
  static const auto scans = mit_csail();
  match(state, scans, static_cast<int>(state.range(0)));
}

}  // namespace

// Pairwise (1), a short map (10) and the default (40): the time per scan against the map size.
BENCHMARK(MatchRoomFlight)->Arg(40)->Unit(benchmark::kMicrosecond);
BENCHMARK(MatchMitCsail)->Arg(1)->Arg(10)->Arg(40)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();

// The MAV text log (docs/mav_log.md), as `scanbus eval mav --log` and sensor_replay read it,
// the records put in time order and paced as the replay does (every due time a number the
// clock can hold, every record published or skipped once), and the true ground a simulated
// log carries (META scenario, boxes, terrain_*) rebuilt and sampled as `scanbus eval mav` does,
// and the laser's scan plane calibrated from it as `scanbus calibrate scan-plane` does.
#include <cmath>
#include <cstdlib>
#include "fuzz_input.hpp"

#include "scanbus/mav_sim/flight.hpp"
#include "scanbus/pose_estimation/scan_plane_calibration.hpp"
#include "scanbus/replay_pacer.hpp"
#include "scanbus/sensor_replay/mav_log.hpp"
#include "scanbus/transforms/transform_buffer.hpp"

namespace {

// A calibration is a finite rotation with a sigma from at least two turns, or a refusal that
// says why.
void calibrate(const scanbus::sensor_replay::MavLog& log) {
  const auto mount = log.meta.find("laser_mount");
  if (mount == log.meta.end() || mount->second.size() != 6) return;
  const auto& m = mount->second;
  std::vector<scanbus::pose_estimation::AttitudeSample> attitudes;
  for (const auto& imu : log.imus) attitudes.push_back({imu.stamp, imu.orientation});
  const auto calibration = scanbus::pose_estimation::calibrate_scan_plane(
      log.lasers, attitudes, scanbus::transforms::from_xyz_rpy({m[0], m[1], m[2]}, {m[3], m[4], m[5]}));
  if (calibration.ok &&
      !(std::isfinite(calibration.rotation) && calibration.sigma >= 0 && calibration.turns.size() >= 2))
    std::abort();
  if (calibration.status.empty()) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const scanbus::fuzz::InputFile file(data, size, "mavlog");
  try {
    const auto log = scanbus::sensor_replay::read_mav_log(file.path());
    const auto records = scanbus::sensor_replay::records_in_time_order(log);
    scanbus::ReplayPacer pacer(8.0, 60.0);
    size_t published = 0, held = 0;
    for (const auto& record : records) {
      const auto step = pacer.next(record.stamp);
      if (static_cast<size_t>(step.publish_held + step.skip_held) != held)
        std::abort();  // a held record is settled once
      published += step.publish_held;
      held = step.hold;
      if (!step.hold && !(step.due >= 0 && step.due <= 1e9)) std::abort();
      published += !step.hold;
    }
    if (pacer.finish() != (held == 1)) std::abort();
    if (published + pacer.skipped() != records.size()) std::abort();
    if (const auto world = scanbus::mav_sim::world_of_log(log)) {
      world->scored_height({1, 0.5}, 0.1);
      world->cast({1, 0.5, 3}, {0.3, 0, -0.954});
    }
    calibrate(log);
  } catch (const scanbus::sensor_replay::MavLogError&) {
  }
  return 0;
}

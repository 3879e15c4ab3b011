#include "scanbus/sim/simulated_scanner.hpp"

#include <cmath>

namespace scanbus::sim {

SimulatedScanner::SimulatedScanner(RoomModel room, ScanPattern pattern, double range_noise, unsigned seed)
    : room_(std::move(room)), pattern_(pattern), noise_(0.0, range_noise), random_(seed) {}

std::vector<SimulatedSample> SimulatedScanner::revolution(int revolution, int cycle) {
  const double pitch = pattern_.pitch(revolution, cycle);
  std::vector<SimulatedSample> samples;
  for (int i = 0; i < pattern_.samples_per_revolution(); ++i) {
    const Eigen::Vector3d direction(std::cos(yaw_) * std::sin(pitch), std::sin(yaw_) * std::sin(pitch),
                                    std::cos(pitch));
    const auto hit = room_.cast(direction);
    const double range = hit ? std::max(0.0, *hit + noise_(random_)) : 0.0;
    samples.push_back({time_, yaw_, pitch, range, hit ? 1000.0 / (1.0 + *hit * *hit) : 0.0});
    yaw_ += pattern_.yaw_step();
    time_ += 1.0 / pattern_.sample_rate;
  }
  return samples;
}

}  // namespace scanbus::sim

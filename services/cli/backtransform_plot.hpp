// BacktransformLaserScan's picture (MAV paper, Algorithm 3.1): scan N and scan N+1 carried
// back by the matched increment, drawn over each other in scan N's frame (PNG, cairo).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace scanbus::cli {

// Throws std::runtime_error naming the file when it cannot be written.
void write_backtransform_plot(const std::string& path, const std::vector<Eigen::Vector2d>& reference,
                              const std::vector<Eigen::Vector2d>& backtransformed, const std::string& title,
                              const std::string& summary);

}  // namespace scanbus::cli

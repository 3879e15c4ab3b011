// BacktransformLaserScan's picture (MAV paper, Algorithm 3.1): scan N and scan N+1 carried
// back by the matched increment, drawn over each other in scan N's frame (PNG, or SVG by
// the file's extension).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace scanbus::plot {

// Points in the laser's frame (m). Throws std::runtime_error naming the file when it cannot
// be written.
void write_backtransform_picture(const std::string& path, const std::vector<Eigen::Vector2d>& reference,
                                 const std::vector<Eigen::Vector2d>& backtransformed, const std::string& title,
                                 const std::string& summary);

}  // namespace scanbus::plot

#include "scanbus/pose_estimation/scan_plane_calibration.hpp"

#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <optional>

namespace scanbus::pose_estimation {

namespace {

constexpr int kLeastPoints = 20;  // returns a scan line needs for its slope

struct SeenScan {
  double stamp = 0;
  Eigen::Matrix3d body;  // attitude of base_link in the map
  double heading = 0;    // rad, of the body's x axis
  std::vector<Eigen::Vector2d> points;
  double residual = 0;  // m, of the points about their line
};

std::optional<Eigen::Quaterniond> attitude_at(const std::vector<AttitudeSample>& attitudes, double stamp,
                                              double max_gap) {
  const auto after = std::lower_bound(attitudes.begin(), attitudes.end(), stamp,
                                      [](const AttitudeSample& a, double t) { return a.stamp < t; });
  if (after == attitudes.end() || after == attitudes.begin()) {
    if (after != attitudes.end() && after->stamp == stamp) return after->orientation;
    return std::nullopt;
  }
  const auto before = std::prev(after);
  const double span = after->stamp - before->stamp;
  if (span > max_gap) return std::nullopt;
  const double weight = span > 0 ? (stamp - before->stamp) / span : 0;
  return before->orientation.slerp(weight, after->orientation);
}

// Each point as (along the body's y axis laid flat, height), in the map's orientation, with
// the laser turned `rotation` in its scan plane.
std::vector<Eigen::Vector2d> profile(const SeenScan& scan, const Eigen::Isometry3d& laser_in_body, double rotation) {
  const Eigen::Matrix3d to_map = scan.body * turned_in_scan_plane(laser_in_body, rotation).linear();
  Eigen::Vector3d across = scan.body.col(1);
  across.z() = 0;
  across.normalize();
  std::vector<Eigen::Vector2d> result;
  result.reserve(scan.points.size());
  for (const auto& p : scan.points) {
    const Eigen::Vector3d v = to_map * Eigen::Vector3d(p.x(), p.y(), 0);
    result.emplace_back(v.dot(across), v.z());
  }
  return result;
}

// The least-squares line z = a + b s: (a, b).
Eigen::Vector2d line_of(const std::vector<Eigen::Vector2d>& points) {
  double n = 0, s = 0, z = 0, ss = 0, sz = 0;
  for (const auto& p : points) {
    const double along = p.x(), height = p.y();
    n += 1, s += along, z += height, ss += along * along, sz += along * height;
  }
  const double slope = (n * sz - s * z) / (n * ss - s * s);
  return {(z - slope * s) / n, slope};
}

// The scan line's slope (dz per m) along the body's y axis laid flat, with the laser turned
// `rotation` in its scan plane. Translations do not change a slope, so only rotations enter.
double cross_slope(const SeenScan& scan, const Eigen::Isometry3d& laser_in_body, double rotation) {
  return line_of(profile(scan, laser_in_body, rotation)).y();
}

// The root mean square of the points about their line: the range noise on level, even
// ground, more over rough ground, steps or mounds.
double residual_about_line(const std::vector<Eigen::Vector2d>& points) {
  const Eigen::Vector2d line = line_of(points);
  double squares = 0;
  for (const auto& p : points) squares += std::pow(p.y() - line.x() - line.y() * p.x(), 2);
  return std::sqrt(squares / static_cast<double>(points.size()));
}

// The points' spread along the line (m, one standard deviation): a line that hardly runs
// across the body (a laser scanning along it, or returns from one spot) has no slope to read.
double spread_along(const std::vector<Eigen::Vector2d>& points) {
  double n = 0, s = 0, ss = 0;
  for (const auto& p : points) n += 1, s += p.x(), ss += p.x() * p.x();
  return std::sqrt(std::max(0.0, ss / n - (s / n) * (s / n)));
}

// The slope's part that does not turn with the heading: least squares of the slopes on a
// constant and the ground's odd harmonics (first and third) of the heading.
double fixed_slope(const std::vector<const SeenScan*>& scans, const Eigen::Isometry3d& laser_in_body, double rotation) {
  Eigen::MatrixXd design(scans.size(), 5);
  Eigen::VectorXd slopes(scans.size());
  for (size_t i = 0; i < scans.size(); ++i) {
    const double h = scans[i]->heading;
    design.row(i) << 1, std::cos(h), std::sin(h), std::cos(3 * h), std::sin(3 * h);
    slopes(i) = cross_slope(*scans[i], laser_in_body, rotation);
  }
  return design.colPivHouseholderQr().solve(slopes)(0);
}

// The rotation that makes the fixed slope zero: Newton's steps on a slope that is close to
// linear in the rotation (its derivative taken once, numerically).
double rotation_of(const std::vector<const SeenScan*>& scans, const Eigen::Isometry3d& laser_in_body) {
  constexpr double kStep = 1e-3;  // rad
  const double at_zero = fixed_slope(scans, laser_in_body, 0);
  const double derivative = (fixed_slope(scans, laser_in_body, kStep) - at_zero) / kStep;
  double rotation = -at_zero / derivative;
  for (int i = 0; i < 2; ++i) rotation -= fixed_slope(scans, laser_in_body, rotation) / derivative;
  return rotation;
}

constexpr double kLeastSpread = 0.1;  // m along the line
constexpr int kSectors = 12;          // of the heading, each whole turn must see every one

// The scans with an attitude and a readable line, in time order.
std::vector<SeenScan> seen_scans(const std::vector<sensor::LaserScan>& scans, std::vector<AttitudeSample> attitudes,
                                 const Eigen::Isometry3d& laser_in_body, const ScanPlaneCalibrationSettings& settings) {
  std::stable_sort(attitudes.begin(), attitudes.end(),
                   [](const AttitudeSample& a, const AttitudeSample& b) { return a.stamp < b.stamp; });
  std::vector<SeenScan> seen;
  for (const auto& scan : scans) {
    const auto attitude = attitude_at(attitudes, scan.stamp, settings.max_attitude_gap);
    if (!attitude) continue;
    SeenScan s{scan.stamp, attitude->normalized().toRotationMatrix(), 0, sensor::kept_points(scan, settings.gate), 0};
    if (s.points.size() < static_cast<size_t>(kLeastPoints)) continue;
    const std::vector<Eigen::Vector2d> line = profile(s, laser_in_body, 0);
    s.residual = residual_about_line(line);
    if (!(spread_along(line) >= kLeastSpread) || !std::isfinite(s.residual)) continue;
    s.heading = std::atan2(s.body(1, 0), s.body(0, 0));
    seen.push_back(std::move(s));
  }
  std::stable_sort(seen.begin(), seen.end(), [](const SeenScan& a, const SeenScan& b) { return a.stamp < b.stamp; });
  return seen;
}

// The scans of each whole turn of the heading, unwrapped from the first scan; `turned` gets
// the turns in all (net: a turn back undoes one).
std::vector<std::vector<const SeenScan*>> whole_turns(const std::vector<SeenScan>& seen, double& turned) {
  std::vector<double> heading(seen.size(), 0);
  for (size_t i = 1; i < seen.size(); ++i)
    heading[i] = heading[i - 1] + std::remainder(seen[i].heading - seen[i - 1].heading, 2 * M_PI);
  turned = std::abs(heading.back()) / (2 * M_PI);
  std::vector<std::vector<const SeenScan*>> turns(static_cast<size_t>(std::floor(turned)));
  for (size_t i = 0; i < seen.size(); ++i) {
    const auto turn = static_cast<size_t>(std::floor(std::abs(heading[i]) / (2 * M_PI)));
    if (turn < turns.size()) turns[turn].push_back(&seen[i]);
  }
  return turns;
}

// The first whole turn with no scan in a sector of the heading (its fit would have no hold on
// the ground's harmonics there), and the sector; none when every turn sees every sector.
std::optional<std::pair<size_t, int>> turn_missing_a_sector(const std::vector<std::vector<const SeenScan*>>& turns) {
  for (size_t turn = 0; turn < turns.size(); ++turn) {
    std::vector<bool> seen(kSectors, false);
    for (const SeenScan* scan : turns[turn])
      seen[static_cast<int>(std::floor((scan->heading + M_PI) / (2 * M_PI) * kSectors)) % kSectors] = true;
    for (int sector = 0; sector < kSectors; ++sector)
      if (!seen[sector]) return std::make_pair(turn, sector);
  }
  return std::nullopt;
}

double median_residual(const std::vector<std::vector<const SeenScan*>>& turns) {
  std::vector<double> residuals;
  for (const auto& turn : turns)
    for (const SeenScan* scan : turn) residuals.push_back(scan->residual);
  std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
  return residuals[residuals.size() / 2];
}

template <typename... Values>
std::string formatted(const char* format, Values... values) {
  char text[320];
  std::snprintf(text, sizeof text, format, values...);
  return text;
}

}  // namespace

Eigen::Isometry3d turned_in_scan_plane(const Eigen::Isometry3d& laser_in_body, double rotation) {
  return laser_in_body * Eigen::AngleAxisd(rotation, Eigen::Vector3d::UnitZ());
}

ScanPlaneCalibration calibrate_scan_plane(const std::vector<sensor::LaserScan>& scans,
                                          const std::vector<AttitudeSample>& attitudes,
                                          const Eigen::Isometry3d& laser_in_body,
                                          const ScanPlaneCalibrationSettings& settings) {
  ScanPlaneCalibration result;
  if (settings.min_turns < 2) {
    result.status = "not measured: min_turns is " + std::to_string(settings.min_turns) +
                    ", at least 2 are needed (the sigma is the turns' spread)";
    return result;
  }
  const std::vector<SeenScan> seen = seen_scans(scans, attitudes, laser_in_body, settings);
  if (seen.empty()) {
    result.status = formatted(
        "not measured: no scan has %d returns spread %.1f m across the body and IMU attitudes within %.2f s around it",
        kLeastPoints, kLeastSpread, settings.max_attitude_gap);
    return result;
  }
  double turned = 0;
  const auto turns = whole_turns(seen, turned);
  if (turns.size() < static_cast<size_t>(settings.min_turns)) {
    result.status = formatted(
        "not measured: the flight turned %.2f times about the vertical, %d whole turns are needed (fly a hover-turn)",
        turned, settings.min_turns);
    return result;
  }
  if (const auto missing = turn_missing_a_sector(turns)) {
    result.status = formatted(
        "not measured: whole turn %zu has no scan at headings %d to %d degrees (IMU gaps, or a stop in the turn)",
        missing->first + 1, missing->second * 360 / kSectors - 180, (missing->second + 1) * 360 / kSectors - 180);
    return result;
  }
  std::vector<const SeenScan*> all;
  for (const auto& turn : turns) all.insert(all.end(), turn.begin(), turn.end());
  result.scans = all.size();
  result.line_residual = median_residual(turns);
  if (!(result.line_residual <= settings.max_line_residual)) {
    result.status = formatted(
        "not measured: the ground under the turns is not level and even (the scan lines' points lie %.3f m about "
        "their lines, more than %.3f m); calibrate over level, even ground",
        result.line_residual, settings.max_line_residual);
    return result;
  }
  for (const auto& turn : turns) result.turns.push_back(rotation_of(turn, laser_in_body));
  const double n = static_cast<double>(result.turns.size());
  const double mean = std::accumulate(result.turns.begin(), result.turns.end(), 0.0) / n;
  double squares = 0;
  for (double r : result.turns) squares += (r - mean) * (r - mean);
  result.rotation = rotation_of(all, laser_in_body);
  // A few turns' spread is itself uncertain: the half-width that holds the error two thirds of
  // the time is Student's t times the standard error, not the standard error.
  const double t = boost::math::quantile(boost::math::students_t(n - 1), 0.8413);
  result.sigma = t * std::sqrt(squares / (n - 1) / n);
  result.ok = std::isfinite(result.rotation) && std::isfinite(result.sigma);
  result.status = result.ok
                      ? formatted("rotation %.3f +- %.3f degrees from %zu whole turns, %zu scans",
                                  result.rotation * 180 / M_PI, result.sigma * 180 / M_PI, turns.size(), result.scans)
                      : "not measured: the scan lines' slopes did not give a finite rotation";
  return result;
}

}  // namespace scanbus::pose_estimation

#include "scanbus/scan_matcher/trajectory.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <optional>
#include <sstream>

namespace scanbus::scan_matcher {

void write_trajectory(const std::string& path, const Trajectory& trajectory) {
  std::ofstream out(path);
  out << std::fixed;
  out.precision(6);
  for (size_t i = 0; i < trajectory.poses.size(); ++i) {
    const Pose2& pose = trajectory.poses[i];
    out << trajectory.stamps[i] << ' ' << pose.x << ' ' << pose.y << ' ' << pose.theta << '\n';
  }
  if (!out) throw LogError(path + ": cannot write the trajectory");
}

Trajectory read_trajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw LogError(path + ": cannot open");
  Trajectory trajectory;
  std::string text;
  for (size_t line = 1; std::getline(in, text); ++line) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream fields(text);
    double stamp;
    Pose2 pose;
    if (!(fields >> stamp >> pose.x >> pose.y >> pose.theta))
      throw LogError(path + ":" + std::to_string(line) + ": expected 'stamp x y theta'");
    trajectory.stamps.push_back(stamp);
    trajectory.poses.push_back(pose);
  }
  return trajectory;
}

TrackedLog track_log(ScanMatcher& matcher, const std::vector<LaserRecord>& records, bool odometry_guess,
                     const std::function<void(size_t, size_t)>& progress) {
  TrackedLog tracked;
  for (size_t i = 0; i < records.size(); ++i) {
    std::optional<Pose2> guess;
    if (odometry_guess && i > 0) guess = records[i - 1].odometry.inverse() * records[i].odometry;
    const auto started = std::chrono::steady_clock::now();
    const MatchResult result = matcher.add_scan(records[i].scan, guess);
    tracked.matching_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    tracked.failed += i > 0 && result.quality != MatchQuality::Ok;
    tracked.qualities.push_back(result.quality);
    tracked.trajectory.stamps.push_back(records[i].scan.stamp);
    tracked.trajectory.poses.push_back(result.pose);
    if (progress) progress(i + 1, records.size());
  }
  return tracked;
}

LogScore score_log(const MatcherSettings& settings, const std::vector<LaserRecord>& records,
                   const std::vector<Relation>& relations, bool odometry_guess, double max_span,
                   const std::function<void(size_t, size_t)>& progress) {
  ScanMatcher matcher(settings);
  LogScore score;
  score.tracked = track_log(matcher, records, odometry_guess, progress);
  const Trajectory& trajectory = score.tracked.trajectory;
  score.all = evaluate_relations(trajectory.stamps, trajectory.poses, relations);
  score.short_span = evaluate_relations(trajectory.stamps, trajectory.poses, relations, max_span);
  score.scans_per_second = static_cast<double>(records.size()) / std::max(score.tracked.matching_seconds, 1e-9);
  return score;
}

}  // namespace scanbus::scan_matcher

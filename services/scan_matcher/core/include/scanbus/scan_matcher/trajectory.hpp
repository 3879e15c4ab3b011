// A log's trajectory as the scan matcher makes it, and the trajectory file that carries one
// between tools (`scanbus scanmatch eval --trajectory`, `scanbus scanmatch score`).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "scanbus/scan_matcher/laser_log.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"

namespace scanbus::scan_matcher {

struct Trajectory {
  std::vector<double> stamps;  // s
  std::vector<Pose2> poses;    // poses[i] at stamps[i]
};

// One line per pose, "stamp x y theta" (s, m, rad), as TUM-style trajectory tools read them;
// lines starting with '#' are comments. Both throw LogError naming the file (and the line).
void write_trajectory(const std::string& path, const Trajectory& trajectory);
Trajectory read_trajectory(const std::string& path);

struct TrackedLog {
  Trajectory trajectory;                // every scan's pose, failed matches held
  std::vector<MatchQuality> qualities;  // of each scan's match (the first: NoReference)
  size_t failed = 0;                    // matches after the first scan that were not Ok
  double matching_seconds = 0;          // wall time inside the matcher
};

// Every scan of the log through `matcher` in order; with `odometry_guess`, the wheel
// odometry's increment is each match's initial guess. `progress(done, total)` after each scan.
TrackedLog track_log(ScanMatcher& matcher, const std::vector<LaserRecord>& records, bool odometry_guess,
                     const std::function<void(size_t, size_t)>& progress = {});

// A log matched from its first scan with `settings`, and scored with the Freiburg metric over
// all its relations and over those at most `max_span` s apart.
struct LogScore {
  TrackedLog tracked;
  RelationErrors all, short_span;
  double scans_per_second = 0;  // inside the matcher
};
LogScore score_log(const MatcherSettings& settings, const std::vector<LaserRecord>& records,
                   const std::vector<Relation>& relations, bool odometry_guess, double max_span,
                   const std::function<void(size_t, size_t)>& progress = {});

}  // namespace scanbus::scan_matcher

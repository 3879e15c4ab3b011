#include "scanbus/cloud_assembly/assembler.hpp"

#include <algorithm>

namespace scanbus::cloud_assembly {

Assembler::Assembler(const AssemblerSettings& settings)
    : settings_(settings),
      buffer_(settings.cache_time),
      continuous_(settings.voxel_size, settings.max_voxels),
      window_(settings.window_age, settings.window_points) {
  buffer_.limit_gap(settings.body_frame, settings.max_pose_gap);
}

void Assembler::add_static(const std::string& parent, const std::string& child, const Eigen::Isometry3d& transform) {
  buffer_.set_static(parent, child, transform);
}

void Assembler::add_transform(const std::string& parent, const std::string& child, double stamp,
                              const Eigen::Isometry3d& transform) {
  buffer_.add(parent, child, stamp, transform);
  newest_ = std::max(newest_, stamp);
}

AssemblyReport Assembler::add_scan(const std::string& frame, sensor::LaserScan scan, double now) {
  newest_ = std::max(newest_, scan.stamp);
  pending_.push_back({frame, std::move(scan)});
  return assemble_ready(now);
}

AssemblyReport Assembler::assemble_ready(double now) {
  AssemblyReport report;
  while (!pending_.empty()) {
    const PendingScan& next = pending_.front();
    std::string why;
    bool in_gap = false;  // no later transform will fill it: dropped at once
    std::optional<Eigen::Isometry3d> to_fixed;
    try {
      to_fixed = buffer_.lookup(settings_.fixed_frame, next.frame, next.scan.stamp);
    } catch (const transforms::TransformGap& gap) {
      why = gap.what(), in_gap = true;
    } catch (const transforms::TransformError& error) {
      why = error.what();
    }
    if (to_fixed) {
      std::vector<Eigen::Vector3d> points = scan_points(next.scan, settings_.gating);
      for (auto& p : points) p = *to_fixed * p;
      continuous_.add(points);
      std::vector<Eigen::Vector3f> window_points(points.size());
      for (size_t i = 0; i < points.size(); ++i) window_points[i] = points[i].cast<float>();
      newest_assembled_ = std::max(newest_assembled_, next.scan.stamp);
      window_.add(next.scan.stamp, std::move(window_points));
      ++report.assembled;
    } else if (in_gap || newest_ - next.scan.stamp > settings_.transform_timeout) {
      ++report.dropped;
      report.problems.push_back("scan dropped: " + why);
    } else {
      say_if_frames_missing(next.frame, why, now, report);
      return report;  // its transform may still come, and later scans wait behind it
    }
    missing_since_.reset();
    missing_said_ = false;
    pending_.pop_front();
  }
  return report;
}

// A scan waiting because no transform joins its frame to the fixed frame at all (no
// rt/tf_static from pose_estimation yet, say) is normal for a moment after a start; past
// a second it is said, naming the frames, before the scans start being dropped.
void Assembler::say_if_frames_missing(const std::string& frame, const std::string& why, double now,
                                      AssemblyReport& report) {
  if (buffer_.connected(settings_.fixed_frame, frame)) return;
  if (!missing_since_) missing_since_ = now;
  if (now - *missing_since_ < 1.0 || missing_said_) return;
  missing_said_ = report.frames_missing = true;
  report.problems.push_back("scans waiting: " + why + "; no transform has joined '" + frame + "' to '" +
                            settings_.fixed_frame + "' yet (rt/tf_static, rt/pose/settled or rt/tf)");
}

WindowReply Assembler::window(double begin, double end, const std::string& frame) const {
  WindowReply reply;
  const std::string target = frame.empty() ? settings_.fixed_frame : frame;
  std::string why;
  std::optional<Eigen::Isometry3d> to_target;
  if (target != settings_.fixed_frame) to_target = buffer_.try_lookup(target, settings_.fixed_frame, end, &why);
  if (!(end >= begin)) {
    reply.status = WindowReply::BadRequest;
    reply.message = "end is before begin";
    return reply;
  }
  if (target != settings_.fixed_frame && !to_target) {
    reply.status = WindowReply::BadRequest;
    reply.message = "no transform to '" + target + "' at the window's end: " + why;
    return reply;
  }
  reply.points = window_.assemble(begin, end);
  if (to_target) {
    const Eigen::Affine3f transform = to_target->cast<float>();
    for (auto& p : reply.points) p = transform * p;
  }
  if (reply.points.empty()) {
    reply.status = WindowReply::Empty;
    reply.message = "no scans between " + std::to_string(begin) + " and " + std::to_string(end) +
                    " (kept: " + std::to_string(window_.oldest()) + " to " + std::to_string(window_.newest()) + ")";
  }
  return reply;
}

}  // namespace scanbus::cloud_assembly

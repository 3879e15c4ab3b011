#include "scanbus/transforms/transform_buffer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace scanbus::transforms {

namespace {

std::string seconds(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", value);
  return text;
}

}  // namespace

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double weight) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translation() = (1 - weight) * a.translation() + weight * b.translation();
  result.linear() = Eigen::Quaterniond(a.linear()).slerp(weight, Eigen::Quaterniond(b.linear())).toRotationMatrix();
  return result;
}

Eigen::Quaterniond from_rpy(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

Eigen::Isometry3d from_xyz_rpy(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.translation() = xyz;
  transform.linear() = from_rpy(rpy.x(), rpy.y(), rpy.z()).toRotationMatrix();
  return transform;
}

void TransformSeries::add(double stamp, const Eigen::Isometry3d& transform) {
  const auto later = std::upper_bound(samples_.begin(), samples_.end(), stamp,
                                      [](double t, const auto& sample) { return t < sample.first; });
  if (later != samples_.begin() && std::prev(later)->first == stamp) {
    std::prev(later)->second = transform;  // a resent sample replaces the old one
  } else {
    samples_.insert(later, {stamp, transform});
  }
  while (samples_.back().first - samples_.front().first > cache_time_) samples_.pop_front();
}

double TransformSeries::outside_by(double stamp) const {
  if (samples_.empty()) return INFINITY;
  if (stamp < oldest()) return stamp - oldest();
  if (stamp > newest()) return stamp - newest();
  return 0;
}

Eigen::Isometry3d TransformSeries::at(double stamp, double max_extrapolation, double max_gap) const {
  if (samples_.empty()) throw TransformError("no transform received yet");
  const double outside = outside_by(stamp);
  if (std::abs(outside) > max_extrapolation) {
    throw TransformError("stamp " + seconds(stamp) + " is " + seconds(std::abs(outside)) + " s " +
                         (outside < 0 ? "before the oldest" : "after the newest") + " transform (" + seconds(oldest()) +
                         " to " + seconds(newest()) + ")");
  }
  if (outside < 0) return samples_.front().second;
  if (outside > 0) return samples_.back().second;
  const auto later = std::lower_bound(samples_.begin(), samples_.end(), stamp,
                                      [](const auto& sample, double t) { return sample.first < t; });
  if (later->first == stamp || later == samples_.begin()) return later->second;
  const auto& before = *std::prev(later);
  if (later->first - before.first > max_gap)
    throw TransformGap("stamp " + seconds(stamp) + " falls in a gap of " + seconds(later->first - before.first) +
                       " s between transforms at " + seconds(before.first) + " and " + seconds(later->first) +
                       " (at most " + seconds(max_gap) + " s is interpolated)");
  return interpolate(before.second, later->second, (stamp - before.first) / (later->first - before.first));
}

TransformBuffer::Edge& TransformBuffer::edge(const std::string& parent, const std::string& child) {
  if (parent.empty() || child.empty() || parent == child)
    throw TransformError("transform '" + parent + "' -> '" + child + "' needs two different, named frames");
  auto found = edges_.find(child);
  if (found == edges_.end()) {
    for (auto up = edges_.find(parent); up != edges_.end(); up = edges_.find(up->second.parent))
      if (up->second.parent == child)
        throw TransformError("transform '" + parent + "' -> '" + child + "' would make '" + child +
                             "' its own ancestor");
  }
  if (found == edges_.end()) found = edges_.emplace(child, Edge{parent, true, {}, TransformSeries(cache_time_)}).first;
  if (found->second.parent != parent)
    throw TransformError("frame '" + child + "' already has parent '" + found->second.parent + "', not '" + parent +
                         "'");
  return found->second;
}

void TransformBuffer::set_static(const std::string& parent, const std::string& child,
                                 const Eigen::Isometry3d& transform) {
  Edge& e = edge(parent, child);
  e.is_static = true;
  e.fixed = transform;
}

void TransformBuffer::add(const std::string& parent, const std::string& child, double stamp,
                          const Eigen::Isometry3d& transform) {
  Edge& e = edge(parent, child);
  e.is_static = false;
  e.series.add(stamp, transform);
}

std::vector<std::string> TransformBuffer::chain(const std::string& frame) const {
  std::vector<std::string> frames{frame};
  // edge() keeps the frames a tree, so this ends at the root.
  for (auto found = edges_.find(frame); found != edges_.end(); found = edges_.find(found->second.parent))
    frames.push_back(found->second.parent);
  return frames;
}

Eigen::Isometry3d TransformBuffer::up_to(const std::string& frame, const std::string& ancestor, double stamp) const {
  Eigen::Isometry3d ancestor_T_frame = Eigen::Isometry3d::Identity();
  for (std::string at = frame; at != ancestor;) {
    const Edge& e = edges_.at(at);
    const auto limited = max_gaps_.find(at);
    const double max_gap = limited == max_gaps_.end() ? INFINITY : limited->second;
    try {
      ancestor_T_frame = (e.is_static ? e.fixed : e.series.at(stamp, max_extrapolation_, max_gap)) * ancestor_T_frame;
    } catch (const TransformGap& gap) {
      throw TransformGap("'" + e.parent + "' -> '" + at + "': " + gap.what());
    } catch (const TransformError& error) {
      throw TransformError("'" + e.parent + "' -> '" + at + "': " + error.what());
    }
    at = e.parent;
  }
  return ancestor_T_frame;
}

Eigen::Isometry3d TransformBuffer::lookup(const std::string& target, const std::string& source, double stamp) const {
  // Only the edges below the frames' lowest common ancestor count, as in tf2.
  const std::vector<std::string> from_source = chain(source), from_target = chain(target);
  const auto common =
      std::find_first_of(from_source.begin(), from_source.end(), from_target.begin(), from_target.end());
  if (common == from_source.end()) {
    throw TransformError("frames '" + target + "' and '" + source + "' are not connected (roots '" +
                         from_target.back() + "' and '" + from_source.back() + "')");
  }
  return up_to(target, *common, stamp).inverse() * up_to(source, *common, stamp);
}

bool TransformBuffer::connected(const std::string& target, const std::string& source) const {
  return chain(target).back() == chain(source).back();  // the same root: one tree
}

std::optional<Eigen::Isometry3d> TransformBuffer::try_lookup(const std::string& target, const std::string& source,
                                                             double stamp, std::string* why) const {
  try {
    return lookup(target, source, stamp);
  } catch (const TransformError& error) {
    if (why) *why = error.what();
    return std::nullopt;
  }
}

}  // namespace scanbus::transforms

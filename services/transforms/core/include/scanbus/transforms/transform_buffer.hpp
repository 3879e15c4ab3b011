// Frames and time, like tf2: static transforms, time-stamped ones kept for a while and
// interpolated (translation linearly, rotation by slerp) at any stamp in between, and a
// clear error for an unknown frame or a stamp too far outside what was received.
#pragma once

#include <Eigen/Geometry>

#include <cmath>

#include <deque>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace scanbus::transforms {

class TransformError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A stamp between two samples further apart than the interpolation may bridge: the source
// stopped in between (a restart), and no later sample will fill the gap.
class TransformGap : public TransformError {
 public:
  using TransformError::TransformError;
};

// One transform over time, e.g. the body's pose in the map. Samples may arrive slightly out
// of order; those older than `cache_time` behind the newest are dropped.
class TransformSeries {
 public:
  explicit TransformSeries(double cache_time = 10.0) : cache_time_(cache_time) {}

  void add(double stamp, const Eigen::Isometry3d& transform);
  // Interpolated at `stamp`; a stamp outside the samples is served by the nearest one when
  // within `max_extrapolation` s of it, otherwise TransformError says by how much it missed.
  // Between samples more than `max_gap` s apart it throws TransformGap.
  Eigen::Isometry3d at(double stamp, double max_extrapolation = 0.0, double max_gap = INFINITY) const;
  // 0 when inside; the seconds before the first sample (negative) or after the newest.
  double outside_by(double stamp) const;
  bool empty() const { return samples_.empty(); }
  double newest() const { return samples_.back().first; }
  double oldest() const { return samples_.front().first; }
  size_t size() const { return samples_.size(); }

 private:
  double cache_time_;
  std::deque<std::pair<double, Eigen::Isometry3d>> samples_;  // by stamp
};

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double weight);

// Rotation from roll, pitch and yaw (rad) as ROS and tf2 take them: yaw about z, then pitch
// about the new y, then roll about the new x (R = Rz(yaw) Ry(pitch) Rx(roll)).
Eigen::Quaterniond from_rpy(double roll, double pitch, double yaw);
// A transform from x y z (m) and roll pitch yaw (rad), as static_transform_publisher takes it.
Eigen::Isometry3d from_xyz_rpy(const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy);

// A tree of frames: each child has one parent, by a static or a time-stamped transform
// (`parent_T_child`, a child point brought into the parent frame).
class TransformBuffer {
 public:
  explicit TransformBuffer(double cache_time = 10.0, double max_extrapolation = 0.0)
      : cache_time_(cache_time), max_extrapolation_(max_extrapolation) {}

  // At most `max_gap` s between two samples of `child`'s transform that a lookup interpolates
  // across (tf2, and every other frame here, bridges any gap): for a transform that comes at
  // a known rate, such as a body pose per scan.
  void limit_gap(const std::string& child, double max_gap) { max_gaps_[child] = max_gap; }

  void set_static(const std::string& parent, const std::string& child, const Eigen::Isometry3d& transform);
  void add(const std::string& parent, const std::string& child, double stamp, const Eigen::Isometry3d& transform);

  // `target_T_source` at `stamp`: a point in `source` brought into `target`. Throws
  // TransformError naming the frame, the edge and the time it could not serve (TransformGap
  // for a stamp in a gap).
  Eigen::Isometry3d lookup(const std::string& target, const std::string& source, double stamp) const;
  // The same without throwing: none, with the reason in `why`.
  std::optional<Eigen::Isometry3d> try_lookup(const std::string& target, const std::string& source, double stamp,
                                              std::string* why = nullptr) const;
  // Whether a chain of transforms joins the frames at all (at some time, if not at every).
  bool connected(const std::string& target, const std::string& source) const;

 private:
  struct Edge {
    std::string parent;
    bool is_static = true;
    Eigen::Isometry3d fixed = Eigen::Isometry3d::Identity();
    TransformSeries series;
  };
  // The frame and its ancestors up to the root.
  std::vector<std::string> chain(const std::string& frame) const;
  // ancestor_T_frame at `stamp`.
  Eigen::Isometry3d up_to(const std::string& frame, const std::string& ancestor, double stamp) const;
  Edge& edge(const std::string& parent, const std::string& child);

  double cache_time_, max_extrapolation_;
  std::map<std::string, Edge> edges_;       // by child
  std::map<std::string, double> max_gaps_;  // by child
};

}  // namespace scanbus::transforms

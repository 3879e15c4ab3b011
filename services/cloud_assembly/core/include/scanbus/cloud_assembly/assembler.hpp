// The service's logic without DDS (the node reads, calls, writes): scans wait in arrival
// order until the transform at their stamp is known (like tf2's message filter), then go
// into the continuous cloud and the window of recent scans; a window is answered in any
// frame the transforms reach.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "scanbus/cloud_assembly/cloud_builder.hpp"
#include "scanbus/transforms/transform_buffer.hpp"

namespace scanbus::cloud_assembly {

struct AssemblerSettings {
  std::string fixed_frame = "map";  // the cloud's frame
  sensor::RangeGate gating;
  double voxel_size = 0.01;              // m, the continuous cloud's voxels
  size_t max_voxels = 5000000;           // its budget
  double window_age = 600.0;             // s of scans kept for window requests
  size_t window_points = 20000000;       // their budget
  double transform_timeout = 2.0;        // s: a scan still without its transform this long after its stamp
                                         // (by the newest stamp seen) is dropped
  double cache_time = 30.0;              // s of transforms kept
  std::string body_frame = "base_link";  // the frame whose pose comes per scan (rt/pose/settled, rt/tf)
  double max_pose_gap = 1.0;  // s: a scan between two poses of body_frame further apart is dropped, not placed
                              // on the straight line between them (the poses stopped: a restart)
};

// What one call did, for Health.
struct AssemblyReport {
  size_t assembled = 0, dropped = 0;
  bool frames_missing = false;        // scans wait for frames no transform joins (said once a wait)
  std::vector<std::string> problems;  // why a scan was dropped; which frames are missing
};

struct WindowReply {
  enum Status { Ok, Empty, BadRequest } status = Ok;
  std::string message;  // why, when not Ok
  std::vector<Eigen::Vector3f> points;
};

class Assembler {
 public:
  explicit Assembler(const AssemblerSettings& settings);

  // Transforms one by one; each throws transforms::TransformError for one that cannot be
  // used. The waiting scans are looked at by assemble_ready(), called once all transforms of
  // a message are in: a chain that the message's last transform completes is then used
  // before the message's newer stamps time any scan out.
  void add_static(const std::string& parent, const std::string& child, const Eigen::Isometry3d& transform);
  void add_transform(const std::string& parent, const std::string& child, double stamp,
                     const Eigen::Isometry3d& transform);
  // `now` (s, a monotonic clock) times how long scans wait for missing frames.
  AssemblyReport assemble_ready(double now);
  // Queues the scan and assembles what is ready.
  AssemblyReport add_scan(const std::string& frame, sensor::LaserScan scan, double now);

  // The window's scans stamped in [begin, end], in `frame` (the fixed frame when empty) as
  // the transforms put it at `end`.
  WindowReply window(double begin, double end, const std::string& frame) const;

  const ContinuousCloud& continuous() const { return continuous_; }
  double newest_stamp() const { return newest_; }                // of a scan or a transform
  double newest_assembled() const { return newest_assembled_; }  // of a scan in the cloud (0: none yet)
  const std::string& fixed_frame() const { return settings_.fixed_frame; }

 private:
  void say_if_frames_missing(const std::string& frame, const std::string& why, double now, AssemblyReport& report);

  struct PendingScan {
    std::string frame;
    sensor::LaserScan scan;
  };
  AssemblerSettings settings_;
  transforms::TransformBuffer buffer_;
  ContinuousCloud continuous_;
  ScanWindow window_;
  std::deque<PendingScan> pending_;
  double newest_ = 0;
  double newest_assembled_ = 0;
  std::optional<double> missing_since_;  // the first scan waiting for frames no transform joins
  bool missing_said_ = false;
};

}  // namespace scanbus::cloud_assembly

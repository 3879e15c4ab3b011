// Thin DDS node: scans wait in a queue until the transform at their stamp is known (like
// tf2's message filter), then go into the continuous cloud and the window of recent scans.
// The continuous cloud and its elevation grid are published every period when it grew;
// requests are answered from the window.
#include "cloud_assembly_node.hpp"

#include <algorithm>
#include <chrono>
#include <deque>
#include <optional>

#include "scanbus/clock.hpp"
#include "scanbus/cloud_assembly/cloud_builder.hpp"
#include "scanbus/cloud_assembly/elevation_grid.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/transforms/transform_buffer.hpp"

namespace scanbus::cloud_assembly {

namespace {

namespace Reply = scanbus::msg::AssembleReply_Constants;

struct Settings {
  std::string fixed_frame;
  ScanGating gating;
  double voxel_size;
  size_t max_voxels;
  double window_age;
  size_t window_points;
  double publish_period;
  double transform_timeout;
  double cache_time;
  ElevationGridSettings elevation;  // cell_size 0: no grid published
};

Settings read_settings(const Config& config) {
  Settings s;
  s.fixed_frame = config.text("fixed_frame", "map");
  s.gating.range_max = config.number("range_max", 30.0, 0.01, 1000);
  s.gating.opening = config.number("opening", 90.0, 1, 360) * M_PI / 180;
  s.voxel_size = config.number("voxel_size", 0.01, 0.001, 10);
  s.max_voxels = static_cast<size_t>(config.integer("max_voxels", 5000000, 1, 1000000000));
  s.window_age = config.number("window_age", 600.0, 0.1, 86400);
  s.window_points = static_cast<size_t>(config.integer("window_points", 20000000, 1, 1000000000));
  s.publish_period = config.number("publish_period", 1.0, 0.05, 3600);
  s.transform_timeout = config.number("transform_timeout", 2.0, 0.0, 600);
  s.cache_time = config.number("cache_time", 30.0, 1.0, 3600);
  const Config elevation = config.section("elevation");
  s.elevation.cell_size = elevation.number("cell_size", 0.5, 0.0, 1000);
  s.elevation.min_points = static_cast<size_t>(elevation.integer("min_points", 3, 1, 1000000));
  return s;
}

Eigen::Isometry3d isometry(const geometry_msgs::msg::Transform& t) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translation() = Eigen::Vector3d(t.translation().x(), t.translation().y(), t.translation().z());
  result.linear() = Eigen::Quaterniond(t.rotation().w(), t.rotation().x(), t.rotation().y(), t.rotation().z())
                        .normalized()
                        .toRotationMatrix();
  return result;
}

// Colours by height between the 2nd and 98th percentile, so a few stray points do not
// wash out the ground's colours.
std::vector<uint32_t> colours_by_height(const std::vector<Eigen::Vector3f>& points) {
  if (points.empty()) return {};
  std::vector<float> heights(points.size());
  for (size_t i = 0; i < points.size(); ++i) heights[i] = points[i].z();
  const auto at = [&](double share) {
    auto it = heights.begin() + static_cast<long>(share * static_cast<double>(heights.size() - 1));
    std::nth_element(heights.begin(), it, heights.end());
    return *it;
  };
  const double low = at(0.02), high = at(0.98);
  std::vector<uint32_t> colours(points.size());
  for (size_t i = 0; i < points.size(); ++i) colours[i] = height_colour(points[i].z(), low, high);
  return colours;
}

struct PendingScan {
  std::string frame;
  LaserScanData scan;
};

class CloudAssembly : public Service {
 public:
  explicit CloudAssembly(ServiceContext& context)
      : log_(context.log),
        health_(context.health),
        settings_(read_settings(context.config.section("cloud_assembly"))),
        buffer_(settings_.cache_time),
        continuous_(settings_.voxel_size, settings_.max_voxels),
        window_(settings_.window_age, settings_.window_points),
        assembled_(context.participant, "rt/cloud/assembled"),
        elevation_(context.participant, "rt/cloud/elevation"),
        replies_(context.participant, "rt/cloud/assemble_reply") {
    tf_static_ = std::make_unique<Reader<tf2_msgs::msg::TFMessagePubSubType>>(
        context.participant, "rt/tf_static", [this](const auto& m, const auto&) { receive(m, true); });
    tf_ = std::make_unique<Reader<tf2_msgs::msg::TFMessagePubSubType>>(
        context.participant, "rt/tf", [this](const auto& m, const auto&) { receive(m, false); });
    scans_ = std::make_unique<Reader<sensor_msgs::msg::LaserScanPubSubType>>(
        context.participant, "rt/scan", [this](const auto& m, const auto&) { receive(m); });
    requests_ = std::make_unique<Reader<scanbus::msg::AssembleRequestPubSubType>>(
        context.participant, "rt/cloud/assemble_request", [this](const auto& m, const auto&) { receive(m); });
  }

  int run() override {
    const auto period = std::chrono::milliseconds(static_cast<long>(settings_.publish_period * 1000));
    while (!StopSignal::wait_for(period)) publish_if_grown();
    requests_.reset();  // no callback may outlive what it uses
    scans_.reset();
    tf_.reset();
    tf_static_.reset();
    publish_if_grown();  // what came in since the last period
    assembled_.wait_for_acknowledgments(std::chrono::seconds(2));
    return 0;
  }

 private:
  void receive(const tf2_msgs::msg::TFMessage& message, bool is_static) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& t : message.transforms()) {
      try {
        if (is_static) {
          buffer_.set_static(t.header().frame_id(), t.child_frame_id(), isometry(t.transform()));
        } else {
          const double stamp = to_seconds(t.header().stamp());
          buffer_.add(t.header().frame_id(), t.child_frame_id(), stamp, isometry(t.transform()));
          newest_ = std::max(newest_, stamp);
        }
      } catch (const transforms::TransformError& e) {
        ++health_.counter("transforms_rejected");
        health_.error(e.what());
      }
    }
    process_pending();
  }

  void receive(const sensor_msgs::msg::LaserScan& message) {
    PendingScan pending{message.header().frame_id(),
                        {to_seconds(message.header().stamp()), message.angle_min(), message.angle_increment(),
                         message.range_min(), message.range_max(), message.ranges()}};
    if (pending.frame.empty() || !std::isfinite(pending.scan.angle_min) || !std::isfinite(pending.scan.angle_increment)) {
      ++health_.counter("scans_rejected");
      health_.error("scan without a frame or with unusable angles");
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    newest_ = std::max(newest_, pending.scan.stamp);
    pending_.push_back(std::move(pending));
    process_pending();
  }

  // Scans in arrival order; one whose transform is still missing `transform_timeout` after
  // its stamp (by the newest stamp seen) is dropped with the reason.
  void process_pending() {
    while (!pending_.empty()) {
      PendingScan& next = pending_.front();
      std::string why;
      if (const auto to_fixed = buffer_.try_lookup(settings_.fixed_frame, next.frame, next.scan.stamp, &why)) {
        std::vector<Eigen::Vector3d> points = scan_points(next.scan, settings_.gating);
        for (auto& p : points) p = *to_fixed * p;
        continuous_.add(points);
        std::vector<Eigen::Vector3f> window_points(points.size());
        for (size_t i = 0; i < points.size(); ++i) window_points[i] = points[i].cast<float>();
        window_.add(next.scan.stamp, std::move(window_points));
        ++health_.counter("scans_assembled");
      } else if (newest_ - next.scan.stamp > settings_.transform_timeout) {
        ++health_.counter("scans_dropped");
        health_.error("scan dropped: " + why);
      } else {
        say_if_frames_missing(next.frame, why);
        return;  // its transform may still come, and later scans wait behind it
      }
      missing_since_.reset();
      missing_said_ = false;
      pending_.pop_front();
    }
  }

  // A scan waiting because no transform joins its frame to the fixed frame at all (no
  // rt/tf_static from pose_estimation yet, say) is normal for a moment after a start; past
  // a second it is said in Health, naming the frames, before the scans start being dropped.
  void say_if_frames_missing(const std::string& frame, const std::string& why) {
    if (buffer_.connected(settings_.fixed_frame, frame)) return;
    const auto now = std::chrono::steady_clock::now();
    if (!missing_since_) missing_since_ = now;
    if (now - *missing_since_ < std::chrono::seconds(1) || missing_said_) return;
    missing_said_ = true;
    ++health_.counter("frames_missing");
    health_.error("scans waiting: " + why + "; no transform has joined '" + frame + "' to '" + settings_.fixed_frame +
                  "' yet (rt/tf_static, rt/tf)");
  }

  void receive(const scanbus::msg::AssembleRequest& request) {
    scanbus::msg::AssembleReply reply;
    reply.request_id(request.request_id());
    reply.client(request.client());
    const double begin = to_seconds(request.begin()), end = to_seconds(request.end());
    const std::string frame = request.frame_id().empty() ? settings_.fixed_frame : request.frame_id();
    std::vector<Eigen::Vector3f> points;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      std::string why;
      std::optional<Eigen::Isometry3d> to_frame;
      if (frame != settings_.fixed_frame) to_frame = buffer_.try_lookup(frame, settings_.fixed_frame, end, &why);
      if (!(end >= begin)) {
        reply.status(Reply::BAD_REQUEST);
        reply.message("end is before begin");
      } else if (frame != settings_.fixed_frame && !to_frame) {
        reply.status(Reply::BAD_REQUEST);
        reply.message("no transform to '" + frame + "' at the window's end: " + why);
      } else {
        points = window_.assemble(begin, end);
        if (to_frame) {
          const Eigen::Affine3f transform = to_frame->cast<float>();
          for (auto& p : points) p = transform * p;
        }
        reply.status(points.empty() ? Reply::EMPTY : Reply::OK);
        reply.message(points.empty() ? "no scans between " + std::to_string(begin) + " and " + std::to_string(end) +
                                           " (kept: " + std::to_string(window_.oldest()) + " to " +
                                           std::to_string(window_.newest()) + ")"
                                     : "");
      }
    }
    reply.cloud(to_coloured_point_cloud2(points, colours_by_height(points), frame, request.end()));
    replies_.write(reply);
    ++health_.counter("requests");
  }

  void publish_if_grown() {
    std::vector<Eigen::Vector3f> points;
    double stamp;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (continuous_.size() == published_size_) return;
      published_size_ = continuous_.size();
      points = continuous_.points();
      stamp = newest_;
      health_.counter("voxels") = continuous_.size();
      health_.counter("voxels_dropped") = continuous_.dropped();
    }
    assembled_.write(to_coloured_point_cloud2(points, colours_by_height(points), settings_.fixed_frame, to_stamp(stamp)));
    ++health_.counter("clouds_published");
    if (settings_.elevation.cell_size > 0) publish_elevation(points, stamp);
  }

  // One point per cell with a height: the cell's centre, its mean height, the spread of its
  // voxels' heights in the fourth field ("stdev").
  void publish_elevation(const std::vector<Eigen::Vector3f>& points, double stamp) {
    ElevationGrid grid;
    try {
      grid = grid_elevation(points, settings_.elevation);
    } catch (const ElevationGridError& e) {
      health_.error(std::string("elevation grid not published: ") + e.what());
      return;
    }
    std::vector<CloudPoint> cells;
    for (const auto& cell : grid.filled_cells()) cells.push_back({cell.top, cell.stdev});
    elevation_.write(to_point_cloud2(cells, settings_.fixed_frame, to_stamp(stamp), "stdev"));
    health_.counter("elevation_cells") = cells.size();
  }

  std::shared_ptr<spdlog::logger> log_;
  HealthReporter& health_;
  Settings settings_;
  std::mutex mutex_;
  transforms::TransformBuffer buffer_;
  ContinuousCloud continuous_;
  ScanWindow window_;
  std::deque<PendingScan> pending_;
  std::optional<std::chrono::steady_clock::time_point> missing_since_;  // frames not joined since
  bool missing_said_ = false;
  double newest_ = 0;
  size_t published_size_ = 0;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> assembled_, elevation_;
  Writer<scanbus::msg::AssembleReplyPubSubType> replies_;
  std::unique_ptr<Reader<tf2_msgs::msg::TFMessagePubSubType>> tf_static_, tf_;
  std::unique_ptr<Reader<sensor_msgs::msg::LaserScanPubSubType>> scans_;
  std::unique_ptr<Reader<scanbus::msg::AssembleRequestPubSubType>> requests_;
};

}  // namespace

std::unique_ptr<Service> make_cloud_assembly(ServiceContext& context) { return std::make_unique<CloudAssembly>(context); }

}  // namespace scanbus::cloud_assembly

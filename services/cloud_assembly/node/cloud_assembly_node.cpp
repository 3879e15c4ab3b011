// Thin DDS node around Assembler (scans, transforms and window requests in; the service's
// logic is there): the continuous cloud and its elevation grid are published every period
// when it grew; requests are answered from the window. The body's pose comes from
// rt/pose/settled (the fusion's heights as they left its window) unless settled_poses is
// false, when rt/tf's, as first solved, places the scans.
#include "cloud_assembly_node.hpp"

#include <algorithm>
#include <chrono>
#include <map>

#include "scanbus/clock.hpp"
#include "scanbus/cloud_assembly/assembler.hpp"
#include "scanbus/cloud_assembly/elevation_grid.hpp"
#include "scanbus/geometry_message.hpp"
#include "scanbus/laser_scan_message.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/palette.hpp"
#include "scanbus/point_cloud.hpp"

namespace scanbus::cloud_assembly {

namespace {

namespace Reply = scanbus::msg::AssembleReply_Constants;

struct Settings {
  AssemblerSettings assembler;
  double publish_period;
  ElevationGridSettings elevation;  // cell_size 0: no grid published
  bool settled_poses;               // the body in fixed_frame from rt/pose/settled, not rt/tf
  std::string body_frame;           // the frame rt/pose/settled places
};

Settings read_settings(const Config& config) {
  Settings s;
  AssemblerSettings& a = s.assembler;
  a.fixed_frame = config.text("fixed_frame", "map");
  a.gating.range_max = config.number("range_max", 30.0, 0.01, 1000);
  a.gating.opening = config.number("opening", 90.0, 1, 360) * M_PI / 180;
  a.voxel_size = config.number("voxel_size", 0.01, 0.001, 10);
  a.max_voxels = static_cast<size_t>(config.integer("max_voxels", 5000000, 1, 1000000000));
  a.window_age = config.number("window_age", 600.0, 0.1, 86400);
  a.window_points = static_cast<size_t>(config.integer("window_points", 20000000, 1, 1000000000));
  a.transform_timeout = config.number("transform_timeout", 6.0, 0.0, 600);
  a.cache_time = config.number("cache_time", 30.0, 1.0, 3600);
  a.max_pose_gap = config.number("max_pose_gap", a.max_pose_gap, 0.001, 3600);
  s.publish_period = config.number("publish_period", 1.0, 0.05, 3600);
  s.settled_poses = config.flag("settled_poses", true);
  s.body_frame = config.text("body_frame", "base_link");
  a.body_frame = s.body_frame;
  const Config elevation = config.section("elevation");
  s.elevation.cell_size = elevation.number("cell_size", 0.5, 0.0, 1000);
  s.elevation.min_points = static_cast<size_t>(elevation.integer("min_points", 3, 1, 1000000));
  return s;
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

class CloudAssembly : public Service {
 public:
  explicit CloudAssembly(ServiceContext& context)
      : log_(context.log),
        health_(context.health),
        settings_(read_settings(context.config.section("cloud_assembly"))),
        assembler_(settings_.assembler),
        assembled_(context.participant, topics::kCloudAssembled),
        elevation_(context.participant, topics::kCloudElevation),
        replies_(context.participant, topics::kAssembleReply) {
    tf_static_ = std::make_unique<Reader<tf2_msgs::msg::TFMessagePubSubType>>(
        context.participant, topics::kTfStatic, [this](const auto& m, const auto&) { receive(m, true); });
    tf_ = std::make_unique<Reader<tf2_msgs::msg::TFMessagePubSubType>>(
        context.participant, topics::kTf, [this](const auto& m, const auto&) { receive(m, false); });
    if (settings_.settled_poses)
      settled_poses_ = std::make_unique<Reader<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType>>(
          context.participant, topics::kPoseSettled, [this](const auto& m, const auto&) { receive(m); });
    scans_ = std::make_unique<Reader<sensor_msgs::msg::LaserScanPubSubType>>(
        context.participant, topics::kScan, [this](const auto& m, const auto&) { receive(m); });
    requests_ = std::make_unique<Reader<scanbus::msg::AssembleRequestPubSubType>>(
        context.participant, topics::kAssembleRequest, [this](const auto& m, const auto&) { receive(m); });
  }

  int run() override {
    const auto period = std::chrono::milliseconds(static_cast<long>(settings_.publish_period * 1000));
    while (!StopSignal::wait_for(period)) publish_if_grown();
    requests_.reset();  // no callback may outlive what it uses
    scans_.reset();
    tf_.reset();
    settled_poses_.reset();
    tf_static_.reset();
    publish_if_grown();  // what came in since the last period
    assembled_.wait_for_acknowledgments(std::chrono::seconds(2));
    return 0;
  }

 private:
  void receive(const tf2_msgs::msg::TFMessage& message, bool is_static) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& t : message.transforms()) {
      if (!is_static && settings_.settled_poses && t.child_frame_id() == settings_.body_frame) continue;
      try {
        const Eigen::Isometry3d transform = to_eigen(t.transform());
        if (is_static)
          assembler_.add_static(t.header().frame_id(), t.child_frame_id(), transform);
        else
          assembler_.add_transform(t.header().frame_id(), t.child_frame_id(), to_seconds(t.header().stamp()),
                                   transform);
      } catch (const transforms::TransformError& e) {
        ++health_.counter("transforms_rejected");
        health_.error(e.what());
      }
    }
    count(assembler_.assemble_ready(steady_seconds()));
  }

  void receive(const geometry_msgs::msg::PoseWithCovarianceStamped& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    try {
      assembler_.add_transform(message.header().frame_id(), settings_.body_frame, to_seconds(message.header().stamp()),
                               to_eigen(message.pose().pose()));
    } catch (const transforms::TransformError& e) {
      ++health_.counter("transforms_rejected");
      health_.error(e.what());
    }
    count(assembler_.assemble_ready(steady_seconds()));
  }

  void receive(const sensor_msgs::msg::LaserScan& message) {
    sensor::LaserScan scan = from_laser_scan_message(message);
    if (message.header().frame_id().empty() || !std::isfinite(scan.angle_min) || !std::isfinite(scan.angle_increment)) {
      ++health_.counter("scans_rejected");
      health_.error("scan without a frame or with unusable angles");
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    count(assembler_.add_scan(message.header().frame_id(), std::move(scan), steady_seconds()));
  }

  void count(const AssemblyReport& report) {
    health_.counter("scans_assembled") += report.assembled;
    health_.counter("scans_dropped") += report.dropped;
    health_.counter("frames_missing") += report.frames_missing;
    for (const auto& problem : report.problems) health_.error(problem);
  }

  void receive(const scanbus::msg::AssembleRequest& request) {
    scanbus::msg::AssembleReply reply;
    reply.request_id(request.request_id());
    reply.client(request.client());
    const double begin = to_seconds(request.begin()), end = to_seconds(request.end());
    WindowReply window;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      window = assembler_.window(begin, end, request.frame_id());
    }
    static const std::map<WindowReply::Status, uint8_t> status = {{WindowReply::Ok, Reply::OK},
                                                                  {WindowReply::Empty, Reply::EMPTY},
                                                                  {WindowReply::BadRequest, Reply::BAD_REQUEST}};
    reply.status(status.at(window.status));
    reply.message(window.message);
    const std::vector<Eigen::Vector3f>& points = window.points;
    const std::string frame = request.frame_id().empty() ? assembler_.fixed_frame() : request.frame_id();
    reply.cloud(to_coloured_point_cloud2(points, colours_by_height(points), frame, request.end()));
    replies_.write(reply);
    ++health_.counter("requests");
  }

  void publish_if_grown() {
    std::vector<Eigen::Vector3f> points;
    double stamp;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const ContinuousCloud& continuous = assembler_.continuous();
      if (continuous.size() == published_size_) return;
      published_size_ = continuous.size();
      points = continuous.points();
      stamp = assembler_.newest_assembled();  // scans wait for their settled pose: the newest in it
      health_.counter("voxels") = continuous.size();
      health_.counter("voxels_dropped") = continuous.dropped();
    }
    assembled_.write(
        to_coloured_point_cloud2(points, colours_by_height(points), assembler_.fixed_frame(), to_stamp(stamp)));
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
    elevation_.write(to_point_cloud2(cells, assembler_.fixed_frame(), to_stamp(stamp), "stdev"));
    health_.counter("elevation_cells") = cells.size();
  }

  std::shared_ptr<spdlog::logger> log_;
  HealthReporter& health_;
  Settings settings_;
  std::mutex mutex_;
  Assembler assembler_;  // under mutex_
  size_t published_size_ = 0;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> assembled_, elevation_;
  Writer<scanbus::msg::AssembleReplyPubSubType> replies_;
  std::unique_ptr<Reader<tf2_msgs::msg::TFMessagePubSubType>> tf_static_, tf_;
  std::unique_ptr<Reader<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType>> settled_poses_;
  std::unique_ptr<Reader<sensor_msgs::msg::LaserScanPubSubType>> scans_;
  std::unique_ptr<Reader<scanbus::msg::AssembleRequestPubSubType>> requests_;
};

}  // namespace

std::unique_ptr<Service> make_cloud_assembly(ServiceContext& context) {
  return std::make_unique<CloudAssembly>(context);
}

}  // namespace scanbus::cloud_assembly

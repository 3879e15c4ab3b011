#include "scanbus/ground_evaluation/box_evaluation.hpp"

#include <ceres/ceres.h>
#include <glog/logging.h>
#include <pcl/ModelCoefficients.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/sac_segmentation.h>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace scanbus::ground_evaluation {

namespace {

// Negative log-likelihood of positions spread evenly over [a, b] and blurred by Gaussian
// noise of sigma = exp(log_sigma): each point's density is
// (Phi((x - a) / sigma) - Phi((x - b) / sigma)) / (b - a).
// Negative log-likelihood of positions spread evenly over [a, b] and blurred by Gaussian
// noise of sigma = exp(log_sigma), with a share w = (1 + tanh(p / 2)) / 2 of stray points spread
// evenly over the whole span of the data (a pass whose pose was off, an edge of the ground
// that joined the cluster): each point's density is
// (1 - w) (Phi((x - a) / sigma) - Phi((x - b) / sigma)) / (b - a) + w / span.
struct BlurredSpread {
  BlurredSpread(std::vector<double> along, double span) : along(std::move(along)), span(span) {}
  template <typename T>
  bool operator()(const T* parameters, T* cost) const {
    const T a = parameters[0], b = parameters[1], sigma = exp(parameters[2]);
    const T stray = T(0.5) * (T(1) + tanh(parameters[3] / T(2)));  // tanh: no overflow as w -> 0
    if (!(b > a)) return false;
    const T scale = T(1) / (sigma * T(std::sqrt(2.0)));
    cost[0] = T(0);
    for (double x : along) {
      const T mass = T(0.5) * (erf((T(x) - a) * scale) - erf((T(x) - b) * scale));
      cost[0] -= log((T(1) - stray) * mass / (b - a) + stray / T(span) + T(1e-12));
    }
    using std::isfinite;       // and ceres::isfinite for Jets, found by argument
    return isfinite(cost[0]);  // a non-finite value or gradient: the line search steps back
  }
  std::vector<double> along;
  double span;
};

// The sides of the points along `axis`, as (low, high). Where the points stop is blurred
// by noise: the maximum-likelihood spread under that blur finds the sides to a fraction of
// the noise, where extremes would stretch with it and quantiles wander with the sample.
struct Extent {
  double low = 0, high = 0;
  double cost = 0;  // the negative log-likelihood at the fit
};
Extent extent(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& axis, double noise_guess) {
  std::vector<double> along(points.size());
  for (size_t i = 0; i < points.size(); ++i) along[i] = points[i].dot(axis);
  const auto [low, high] = std::minmax_element(along.begin(), along.end());
  if (!(*high > *low)) return {*low, *high, INFINITY};
  const double span = *high - *low + 2 * noise_guess;
  double parameters[4] = {*low, *high, std::log(noise_guess), -4.0};  // 2 % strays to start
  ceres::GradientProblem problem(
      new ceres::AutoDiffFirstOrderFunction<BlurredSpread, 4>(new BlurredSpread(std::move(along), span)));
  ceres::GradientProblemSolver::Options options;
  options.max_num_iterations = 100;
  options.logging_type = ceres::SILENT;
  options.function_tolerance = 1e-12;  // the cost is a sum over many points: tiny relative changes still move the sides
  options.gradient_tolerance = 1e-10;
  options.parameter_tolerance = 1e-12;
  // Ceres's line search warns through glog when a step's interpolating polynomial is flat
  // (harmless: it bisects then); a user's terminal should not fill with it.
  FLAGS_minloglevel = std::max(FLAGS_minloglevel, static_cast<int>(google::GLOG_ERROR));
  ceres::GradientProblemSolver::Summary summary;
  ceres::Solve(options, problem, parameters, &summary);
  return {parameters[0], parameters[1], summary.final_cost};
}

// Area of the bounding rectangle at `yaw`. Its orientation comes from the outermost points
// (a quantile would cut a tilted rectangle's corners and favour wrong angles); its size
// then from the quantiles.
double bounding_area(const std::vector<Eigen::Vector2d>& points, double yaw) {
  const Eigen::Vector2d u(std::cos(yaw), std::sin(yaw)), v(-std::sin(yaw), std::cos(yaw));
  double low_u = INFINITY, high_u = -INFINITY, low_v = INFINITY, high_v = -INFINITY;
  for (const auto& p : points) {
    low_u = std::min(low_u, p.dot(u)), high_u = std::max(high_u, p.dot(u));
    low_v = std::min(low_v, p.dot(v)), high_v = std::max(high_v, p.dot(v));
  }
  return (high_u - low_u) * (high_v - low_v);
}

// The plane with most inliers among those within `tilt` (degrees) of horizontal, RANSAC, its
// normal up; on centred coordinates (RANSAC is unstable far from the origin).
bool fit_ground(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, double threshold, Eigen::Vector4d& plane,
                double tilt = 15, pcl::PointIndices* inliers_out = nullptr) {
  pcl::SACSegmentation<pcl::PointXYZ> segmentation;
  segmentation.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
  segmentation.setMethodType(pcl::SAC_RANSAC);
  segmentation.setAxis(Eigen::Vector3f::UnitZ());
  segmentation.setEpsAngle(tilt * M_PI / 180);
  segmentation.setDistanceThreshold(threshold);
  segmentation.setMaxIterations(500);
  segmentation.setInputCloud(cloud);
  pcl::PointIndices inliers;
  pcl::ModelCoefficients coefficients;
  segmentation.segment(inliers, coefficients);
  if (inliers.indices.empty() || coefficients.values.size() != 4) return false;
  if (inliers_out) *inliers_out = std::move(inliers);
  plane =
      Eigen::Vector4d(coefficients.values[0], coefficients.values[1], coefficients.values[2], coefficients.values[3]);
  plane /= plane.head<3>().norm();
  if (plane.z() < 0) plane = -plane;  // height above it is positive
  return true;
}

// The ground under each point, so the boxes stand out of a slope or a mound as they do out
// of a level floor: a plane for every `kCell` cell, fitted (fit_ground) to the points of
// the 2.5 m square around it (kReach cells each way), where the boxes are a minority (two
// 0.6 x 0.4 m boxes fill under a tenth of it) and fall out as outliers.
class LocalGround {
 public:
  LocalGround(const pcl::PointCloud<pcl::PointXYZ>& cloud, double threshold) {
    std::map<Cell, std::vector<size_t>> members;
    for (size_t i = 0; i < cloud.size(); ++i) members[cell_of(cloud[i])].push_back(i);
    for (const auto& [cell, unused] : members) {
      pcl::PointCloud<pcl::PointXYZ>::Ptr near(new pcl::PointCloud<pcl::PointXYZ>);
      const Eigen::Vector3f middle((cell.first + 0.5f) * kCell, (cell.second + 0.5f) * kCell, 0);
      for (long dx = -kReach; dx <= kReach; ++dx)
        for (long dy = -kReach; dy <= kReach; ++dy) {
          const auto found = members.find({cell.first + dx, cell.second + dy});
          if (found == members.end()) continue;
          // Every n-th point: a few thousand define a plane as well as all of them.
          const size_t stride = std::max<size_t>(1, found->second.size() / 300);
          for (size_t k = 0; k < found->second.size(); k += stride) {
            const auto& p = cloud[found->second[k]];
            near->push_back(pcl::PointXYZ(p.x - middle.x(), p.y - middle.y(), p.z));
          }
        }
      Eigen::Vector4d plane;
      if (near->size() >= kLeastPoints && fit_ground(near, threshold, plane)) {
        plane.w() -= plane.x() * middle.x() + plane.y() * middle.y();  // back to the cloud's coordinates
        planes_[cell] = plane;
      }
    }
  }
  bool empty() const { return planes_.empty(); }
  // Height of `p` above the ground under it; none where the ground is not known.
  std::optional<double> height_above(const pcl::PointXYZ& p) const {
    const auto found = planes_.find(cell_of(p));
    if (found == planes_.end()) return std::nullopt;
    return found->second.dot(Eigen::Vector4d(p.x, p.y, p.z, 1));
  }

 private:
  using Cell = std::pair<long, long>;
  static constexpr double kCell = 0.5;        // m
  static constexpr long kReach = 2;           // cells each way: the plane is fitted over 2.5 m x 2.5 m
  static constexpr size_t kLeastPoints = 50;  // in those cells
  static Cell cell_of(const pcl::PointXYZ& p) {
    return {static_cast<long>(std::floor(p.x / kCell)), static_cast<long>(std::floor(p.y / kCell))};
  }
  std::map<Cell, Eigen::Vector4d> planes_;
};

}  // namespace

Footprint fit_footprint(const std::vector<Eigen::Vector2d>& points, double noise) {
  Footprint footprint;
  if (points.size() < 3) return footprint;
  // Coarse search over a quarter turn (a rectangle repeats), then a fine one around the best.
  double best = 0, best_area = INFINITY;
  for (double step : {0.5, 0.02}) {
    const double centre = best, span = step == 0.5 ? 45.0 : 0.5;
    for (double degrees = -span; degrees < span; degrees += step) {
      const double yaw = (centre + degrees) * M_PI / 180;
      const double area = bounding_area(points, yaw);
      if (area < best_area) best_area = area, best = centre + degrees;
    }
  }
  // The outermost points set the orientation to within their noise; the sides fit best
  // (sharpest) at the true one: refine within 2 degrees by the fits' likelihood.
  const auto fit_at = [&](double degrees, Extent& a, Extent& b) {
    const double yaw = degrees * M_PI / 180;
    a = extent(points, {std::cos(yaw), std::sin(yaw)}, noise);
    b = extent(points, {-std::sin(yaw), std::cos(yaw)}, noise);
    return a.cost + b.cost;
  };
  Extent a, b, best_a, best_b;
  double best_cost = INFINITY, refined = best;
  for (double degrees = best - 2; degrees <= best + 2 + 1e-9; degrees += 0.1) {
    const double cost = fit_at(degrees, a, b);
    if (cost < best_cost) best_cost = cost, refined = degrees, best_a = a, best_b = b;
  }
  a = best_a, b = best_b;
  double yaw = refined * M_PI / 180;
  Eigen::Vector2d u(std::cos(yaw), std::sin(yaw)), v(-std::sin(yaw), std::cos(yaw));
  if (a.high - a.low < b.high - b.low) {  // the length axis is the longer side
    std::swap(a, b);
    std::swap(u, v);
    yaw += M_PI / 2;
  }
  footprint.yaw = std::remainder(yaw, M_PI);
  footprint.length = a.high - a.low;
  footprint.width = b.high - b.low;
  footprint.centre = u * (a.low + a.high) / 2 + v * (b.low + b.high) / 2;
  return footprint;
}

namespace {

// A box's footprint is drawn from its top alone (its sides, seen at a slant, would widen
// it): the top is the plane with most of the box's points among near-horizontal ones, level
// or tilted with the ground the box stands on, and the footprint is measured in it.
struct Top {
  std::vector<Eigen::Vector2d> points;  // along e1 and e2 from `origin`
  Eigen::Vector3d origin = Eigen::Vector3d::Zero(), e1 = Eigen::Vector3d::UnitX(), e2 = Eigen::Vector3d::UnitY();
};
Top top_of(const pcl::PointCloud<pcl::PointXYZ>& above, const pcl::PointIndices& cluster, double band) {
  Top top;
  for (int index : cluster.indices) top.origin += above[static_cast<size_t>(index)].getVector3fMap().cast<double>();
  top.origin /= static_cast<double>(cluster.indices.size());
  pcl::PointCloud<pcl::PointXYZ>::Ptr points(new pcl::PointCloud<pcl::PointXYZ>);
  for (int index : cluster.indices) {
    const Eigen::Vector3d p = above[static_cast<size_t>(index)].getVector3fMap().cast<double>() - top.origin;
    points->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
  }
  Eigen::Vector4d plane;
  pcl::PointIndices inliers;
  if (!fit_ground(points, band, plane, 20, &inliers)) return top;
  const Eigen::Vector3d normal = plane.head<3>();
  // Axes in the top: e1 under x, e2 under y (a level top keeps the map's axes).
  top.e1 = (Eigen::Vector3d::UnitX() - normal.x() * normal).normalized();
  top.e2 = normal.cross(top.e1);
  for (int inlier : inliers.indices) {
    const Eigen::Vector3d p = (*points)[static_cast<size_t>(inlier)].getVector3fMap().cast<double>();
    top.points.emplace_back(p.dot(top.e1), p.dot(top.e2));
  }
  return top;
}

// How an object's points spread on the ground: their mean, principal axes and the
// half-sides of the rectangle an even spread that wide would cover (variance h^2 / 3).
struct Spread {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d axes = Eigen::Matrix2d::Identity();
  Eigen::Vector2d half = Eigen::Vector2d::Zero();
};
Spread spread_of(const pcl::PointCloud<pcl::PointXYZ>& above, const pcl::PointIndices& cluster) {
  Spread spread;
  for (int index : cluster.indices)
    spread.mean += above[static_cast<size_t>(index)].getVector3fMap().head<2>().cast<double>();
  spread.mean /= static_cast<double>(cluster.indices.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (int index : cluster.indices) {
    const Eigen::Vector2d d = above[static_cast<size_t>(index)].getVector3fMap().head<2>().cast<double>() - spread.mean;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter / static_cast<double>(cluster.indices.size()));
  spread.axes = solver.eigenvectors();
  spread.half = (3 * solver.eigenvalues().cwiseMax(1e-12)).cwiseSqrt();
  return spread;
}

// Whether an object has sides: just outside the rectangle its points cover (5 to 15 cm
// beyond it) lies ground, nearer the ground's level than half the height objects are cut
// at (`cut`). A box does; the crown of a mound that the local ground planes cut off does not
// (found on a 0.4 m mound beside the boxes: its crown, 0.17 m above the planes, was nearer
// the boxes' size than a box, and around it the mound stood 0.07 m above them), nor does a
// bank: what lies around them is just under the cut.
bool has_sides(const Spread& spread, double cut, const pcl::PointCloud<pcl::PointXYZ>& cloud,
               const std::vector<std::optional<double>>& above_ground) {
  constexpr double kNear = 0.05, kFar = 0.15;  // m beyond the rectangle: past the blur of its edge
  constexpr size_t kLeastAround = 10;          // fewer points around say nothing
  // The grown rectangle's reach along x and y: most points fall outside it at two compares.
  const Eigen::Vector2d reach = spread.axes.cwiseAbs() * (spread.half + Eigen::Vector2d::Constant(kFar));
  std::vector<double> around;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (!above_ground[i] || std::abs(cloud[i].x - spread.mean.x()) > reach.x() ||
        std::abs(cloud[i].y - spread.mean.y()) > reach.y())
      continue;
    const Eigen::Vector2d local =
        spread.axes.transpose() * (cloud[i].getVector3fMap().head<2>().cast<double>() - spread.mean);
    const double beyond = (local.cwiseAbs() - spread.half).maxCoeff();
    if (beyond > kNear && beyond <= kFar) around.push_back(*above_ground[i]);
  }
  if (around.size() < kLeastAround) return true;  // too little seen around it: no evidence against a box
  const auto middle = around.begin() + static_cast<long>(around.size() / 2);
  std::nth_element(around.begin(), middle, around.end());
  return *middle < cut / 2;
}

// The height of an object's top: most of a box's points lie on its top, the highest are noise.
double top_height(const pcl::PointIndices& cluster, const std::vector<double>& heights) {
  std::vector<double> cluster_heights;
  for (int index : cluster.indices) cluster_heights.push_back(heights[static_cast<size_t>(index)]);
  const auto at = cluster_heights.begin() + static_cast<long>(0.75 * static_cast<double>(cluster_heights.size() - 1));
  std::nth_element(cluster_heights.begin(), at, cluster_heights.end());
  return *at;
}

}  // namespace

BoxEvaluation evaluate_boxes(const std::vector<Eigen::Vector3f>& cloud, double truth_width, double truth_length,
                             const BoxSearchSettings& settings) {
  BoxEvaluation result;
  if (!(truth_width > 0 && truth_length > 0)) {
    result.message = "the true width and length must be positive";
    return result;
  }
  result.ratio_actual = std::min(truth_width, truth_length) / std::max(truth_width, truth_length);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  size_t finite = 0;
  for (const auto& p : cloud)
    if (p.allFinite()) centre += p.cast<double>(), ++finite;
  if (finite < 100) {
    result.message = "the cloud has " + std::to_string(finite) + " points, too few to find a ground";
    return result;
  }
  centre /= static_cast<double>(finite);
  pcl::PointCloud<pcl::PointXYZ>::Ptr centred(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& p : cloud)
    if (p.allFinite()) centred->push_back(pcl::PointXYZ(p.x() - centre.x(), p.y() - centre.y(), p.z() - centre.z()));
  const LocalGround ground(*centred, settings.ground_threshold);
  if (ground.empty()) {
    result.message = "no ground plane found";
    return result;
  }
  // A cloud built over several passes has a ground as thick as the heights' errors between
  // passes: objects start above that (four robust sigmas of the ground's heights).
  std::vector<std::optional<double>> above_ground(centred->size());  // each point's, looked up once
  for (size_t i = 0; i < centred->size(); ++i) above_ground[i] = ground.height_above((*centred)[i]);
  std::vector<double> near_ground;
  for (const auto& height : above_ground)
    if (height && std::abs(*height) < 2 * settings.min_height) near_ground.push_back(std::abs(*height));
  const auto middle = near_ground.begin() + static_cast<long>(near_ground.size() / 2);
  std::nth_element(near_ground.begin(), middle, near_ground.end());
  result.ground_sigma = near_ground.empty() ? 0 : 1.4826 * *middle;
  const double min_height = std::max(settings.min_height, 4 * result.ground_sigma);
  pcl::PointCloud<pcl::PointXYZ>::Ptr above(new pcl::PointCloud<pcl::PointXYZ>);
  std::vector<double> heights;
  for (size_t i = 0; i < centred->size(); ++i) {
    const double height = above_ground[i].value_or(0);  // ground not known: not an object
    if (height > min_height) {
      above->push_back((*centred)[i]);
      heights.push_back(height);
    } else if (std::abs(height) <= settings.ground_threshold) {
      ++result.ground_points;
    }
  }
  std::vector<pcl::PointIndices> clusters;
  if (!above->empty()) {
    pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
    pcl::EuclideanClusterExtraction<pcl::PointXYZ> extraction;
    extraction.setClusterTolerance(settings.cluster_tolerance);
    extraction.setMinClusterSize(static_cast<int>(settings.min_cluster_points));
    extraction.setMaxClusterSize(std::numeric_limits<int>::max());
    extraction.setSearchMethod(tree);
    extraction.setInputCloud(above);
    extraction.extract(clusters);  // largest first
  }
  if (clusters.size() < settings.boxes) {
    result.message = "found " + std::to_string(clusters.size()) + " objects above the ground, expected " +
                     std::to_string(settings.boxes) + " boxes";
    return result;
  }
  // The boxes are the objects with sides whose size on the ground is nearest the boxes'
  // known footprint: a ridge of ground where the MAV hovered with a wrong height, or a pile
  // of stray returns, may be larger, but is not box-sized. (Only the area is compared: the
  // width/length ratio P measures is left free.) Objects without sides, or longer than
  // kLongest boxes, come after the others, so that too few of those still gives a
  // measurement: a strip along a step's edge, which the local ground planes cut off, had a
  // box's area (1.06 x 0.09 m beside the boxes over issue 19's steps).
  constexpr double kLongest = 1.5;                 // times the boxes' length: longer is no box
  std::vector<std::pair<double, size_t>> by_size;  // mismatch, cluster
  std::vector<Spread> spreads;
  for (size_t c = 0; c < clusters.size(); ++c) {
    spreads.push_back(spread_of(*above, clusters[c]));
    const double area = 4 * spreads.back().half.x() * spreads.back().half.y();
    by_size.emplace_back(std::abs(std::log(area / (truth_width * truth_length))), c);
  }
  std::stable_sort(by_size.begin(), by_size.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<size_t> chosen, unlike;  // unlike a box: no sides, or too long
  for (const auto& [mismatch, c] : by_size) {
    if (chosen.size() == settings.boxes) break;
    // The length first: has_sides reads the cloud around the object.
    const bool box_like = 2 * spreads[c].half.maxCoeff() <= kLongest * std::max(truth_width, truth_length) &&
                          has_sides(spreads[c], min_height, *centred, above_ground);
    (box_like ? chosen : unlike).push_back(c);
  }
  for (size_t k = 0; chosen.size() < settings.boxes; ++k) chosen.push_back(unlike[k]);
  double total = 0;
  for (size_t c : chosen) {
    const pcl::PointIndices& cluster = clusters[c];
    const double top = top_height(cluster, heights);
    const Top box_top = top_of(*above, cluster, settings.top_band);
    const Footprint footprint = fit_footprint(box_top.points, settings.noise);
    BoxMeasurement box;
    const Eigen::Vector3d middle =
        box_top.origin + footprint.centre.x() * box_top.e1 + footprint.centre.y() * box_top.e2;
    box.centre = (middle + centre).head<2>();
    const Eigen::Vector3d length_axis = std::cos(footprint.yaw) * box_top.e1 + std::sin(footprint.yaw) * box_top.e2;
    box.yaw = std::remainder(std::atan2(length_axis.y(), length_axis.x()), M_PI);
    box.length = footprint.length;
    box.width = footprint.width;
    box.height = top;
    box.points = cluster.indices.size();
    const double ratio = box.length > 0 ? box.width / box.length : 0;
    box.error_percent = std::abs(ratio - result.ratio_actual) / result.ratio_actual * 100;
    box.performance_percent = 100 - box.error_percent;
    total += box.performance_percent;
    result.boxes.push_back(box);
  }
  result.mean_performance_percent = total / static_cast<double>(settings.boxes);
  result.ok = true;
  return result;
}

}  // namespace scanbus::ground_evaluation

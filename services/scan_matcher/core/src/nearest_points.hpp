// Nearest-neighbour search over 2D points (nanoflann's k-d tree); shared by the matcher's map
// and BacktransformLaserScan's residuals. Not installed: nanoflann stays out of the public headers.
#pragma once

#include <Eigen/Core>
#include <nanoflann.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace scanbus::scan_matcher {

class NearestPoints {
 public:
  // nanoflann 1.4 builds the tree in its constructor (set_ is initialised before tree_).
  explicit NearestPoints(std::vector<Eigen::Vector2d> points) : set_{std::move(points)} {}
  NearestPoints(const NearestPoints&) = delete;  // the tree refers to the points
  NearestPoints& operator=(const NearestPoints&) = delete;

  struct Found {
    size_t index;
    double distance_squared;
  };
  // The point nearest to `query`; there must be at least one.
  Found nearest(const Eigen::Vector2d& query) const {
    unsigned int index = 0;  // nanoflann 1.4's index type
    double distance_squared = 0;
    tree_.knnSearch(query.data(), 1, &index, &distance_squared);
    return {index, distance_squared};
  }
  static constexpr size_t npos = static_cast<size_t>(-1);
  static constexpr size_t kKept = 4;
  // The kKept points nearest to `query` closer than sqrt(bound_squared), nearest first, and
  // the squared distance within which there are no others (the last's, or the bound).
  struct Nearby {
    std::array<unsigned int, kKept> index;  // nanoflann 1.4's index type
    std::array<double, kKept> distance_squared;
    size_t count = 0;
    double radius_squared = 0;
  };
  Nearby nearby(const Eigen::Vector2d& query, double bound_squared) const {
    Nearby found;
    nanoflann::KNNResultSet<double, unsigned int, size_t> result(kKept);
    result.init(found.index.data(), found.distance_squared.data());
    found.distance_squared.back() = bound_squared;  // the search starts bounded
    tree_.findNeighbors(result, query.data(), nanoflann::SearchParams());
    found.count = result.size();
    found.radius_squared = result.worstDist();
    return found;
  }
  const std::vector<Eigen::Vector2d>& points() const { return set_.points; }

 private:
  struct PointSet {
    std::vector<Eigen::Vector2d> points;
    size_t kdtree_get_point_count() const { return points.size(); }
    double kdtree_get_pt(size_t index, size_t dim) const { return points[index][static_cast<int>(dim)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointSet>, PointSet, 2>;

  PointSet set_;
  KdTree tree_{2, set_, {10}};
};

// The nearest map point to a query that moves a little between calls: one scan point over the
// iterations of an alignment. The points nearby are searched once; while the query stays among
// them (the nearest of them nearer than the search radius less the distance moved: no other
// point can be, by the triangle inequality) they give the same answer as a search would.
// After the first steps the pose moves millimetres and most queries need no search (half the
// matcher's time went into searches before). The points it keeps are indices into one map:
// a MovingQuery serves one map only (align_to makes new ones for each alignment).
class MovingQuery {
 public:
  // The nearest point to `query` if it is within `max_distance` (index npos if none).
  NearestPoints::Found nearest(const NearestPoints& map, const Eigen::Vector2d& query, double max_distance) {
    NearestPoints::Found best = among_nearby(map, query);
    // Shrunk by a part in 1e12: the square roots' rounding never decides a near tie.
    const double clear = (radius_ - (query - searched_at_).norm()) * (1 - 1e-12);
    const bool sure = best.distance_squared < clear * clear && clear > 0;
    const bool none_near = clear > max_distance;  // nothing else within max_distance
    if (!sure && !none_near) {
      // Searched a quarter past max_distance, so that a query with nothing near may move too.
      const double bound = 1.25 * max_distance;
      nearby_ = map.nearby(query, bound * bound);
      radius_ = std::sqrt(nearby_.radius_squared);
      searched_at_ = query;
      best = among_nearby(map, query);
    }
    if (best.distance_squared > max_distance * max_distance) return {NearestPoints::npos, best.distance_squared};
    return best;
  }

 private:
  NearestPoints::Found among_nearby(const NearestPoints& map, const Eigen::Vector2d& query) const {
    NearestPoints::Found best{NearestPoints::npos, std::numeric_limits<double>::infinity()};
    for (size_t k = 0; k < nearby_.count; ++k) {
      const double distance_squared = (map.points()[nearby_.index[k]] - query).squaredNorm();
      if (distance_squared < best.distance_squared) best = {nearby_.index[k], distance_squared};
    }
    return best;
  }

  NearestPoints::Nearby nearby_;
  double radius_ = 0;  // m: no other point is nearer to searched_at_
  Eigen::Vector2d searched_at_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
};

}  // namespace scanbus::scan_matcher

// Nearest-neighbour search over 2D points (nanoflann's k-d tree); shared by the matcher's map
// and BacktransformLaserScan's residuals. Not installed: nanoflann stays out of the public headers.
#pragma once

#include <Eigen/Core>
#include <nanoflann.hpp>

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
  // The two points nearest to `query` closer than sqrt(bound_squared): the nearest's index (npos
  // if none) and both squared distances (bound_squared where there is none). The second tells
  // how far the query may move before another point could be nearer.
  static constexpr size_t npos = static_cast<size_t>(-1);
  struct TwoFound {
    size_t index;
    double distance_squared, second_squared;
  };
  TwoFound nearest_two(const Eigen::Vector2d& query, double bound_squared) const {
    WithinBound found{npos, bound_squared, bound_squared};
    tree_.findNeighbors(found, query.data(), nanoflann::SearchParams());
    return {found.index, found.first, found.second};
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
  // nanoflann's result-set interface for the two nearest within a bound: its KNNResultSet starts
  // unbounded, this one at the bound, and the search skips every branch beyond it.
  struct WithinBound {
    size_t index;
    double first, second;  // squared distances
    double worstDist() const { return second; }
    bool full() const { return index != npos; }
    bool addPoint(double distance_squared, unsigned int point) {
      if (distance_squared < first) {
        second = first;
        first = distance_squared;
        index = point;
      } else if (distance_squared < second) {
        second = distance_squared;
      }
      return true;
    }
  };
  using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointSet>, PointSet, 2>;

  PointSet set_;
  KdTree tree_{2, set_, {10}};
};

}  // namespace scanbus::scan_matcher

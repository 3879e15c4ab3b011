#include "scanbus/point_cloud.hpp"

#include <cstddef>
#include <cstring>

namespace scanbus {

namespace {

constexpr uint32_t kPointStep = 16;

sensor_msgs::msg::PointField float_field(const char* name, uint32_t offset) {
  sensor_msgs::msg::PointField field;
  field.name(name);
  field.offset(offset);
  field.datatype(sensor_msgs::msg::PointField_Constants::FLOAT32);
  field.count(1);
  return field;
}

// Offset of a float32 field, or -1 when the cloud has no such field.
int float_offset(const sensor_msgs::msg::PointCloud2& cloud, const std::string& name) {
  for (const auto& field : cloud.fields()) {
    if (field.name() != name) continue;
    if (field.datatype() != sensor_msgs::msg::PointField_Constants::FLOAT32)
      throw std::invalid_argument("PointCloud2 field '" + name + "' is not float32");
    if (field.offset() + 4 > cloud.point_step())
      throw std::invalid_argument("PointCloud2 field '" + name + "' lies outside point_step");
    return static_cast<int>(field.offset());
  }
  return -1;
}

// An unorganised cloud of `count` points x y z and one more float32 field, data allocated.
sensor_msgs::msg::PointCloud2 sized_cloud(const char* fourth_field, size_t count, const std::string& frame_id,
                                          const builtin_interfaces::msg::Time& stamp) {
  sensor_msgs::msg::PointCloud2 cloud;
  cloud.header().frame_id(frame_id);
  cloud.header().stamp(stamp);
  cloud.fields({float_field("x", 0), float_field("y", 4), float_field("z", 8), float_field(fourth_field, 12)});
  cloud.height(1);
  cloud.width(static_cast<uint32_t>(count));
  cloud.is_bigendian(false);
  cloud.point_step(kPointStep);
  cloud.row_step(kPointStep * cloud.width());
  cloud.is_dense(true);
  cloud.data().resize(count * kPointStep);
  return cloud;
}

}  // namespace

sensor_msgs::msg::PointCloud2 to_point_cloud2(const std::vector<CloudPoint>& points, const std::string& frame_id,
                                              const builtin_interfaces::msg::Time& stamp, const char* fourth_field) {
  sensor_msgs::msg::PointCloud2 cloud = sized_cloud(fourth_field, 0, frame_id, stamp);
  cloud.width(static_cast<uint32_t>(points.size()));
  cloud.row_step(kPointStep * cloud.width());
  // CloudPoint's bytes are the cloud's layout (x y z intensity float32): one copy, no
  // zero-filling first (a million points are 16 MB).
  static_assert(sizeof(CloudPoint) == kPointStep && offsetof(CloudPoint, intensity) == 12);
  const auto* bytes = reinterpret_cast<const uint8_t*>(points.data());
  cloud.data().assign(bytes, bytes + points.size() * kPointStep);
  return cloud;
}

sensor_msgs::msg::PointCloud2 to_coloured_point_cloud2(const std::vector<Eigen::Vector3f>& points,
                                                       const std::vector<uint32_t>& colours,
                                                       const std::string& frame_id,
                                                       const builtin_interfaces::msg::Time& stamp) {
  if (colours.size() != points.size()) throw std::invalid_argument("one colour per point is needed");
  sensor_msgs::msg::PointCloud2 cloud = sized_cloud("rgb", points.size(), frame_id, stamp);
  uint8_t* out = cloud.data().data();
  for (size_t i = 0; i < points.size(); ++i) {
    std::memcpy(out, points[i].data(), 12);
    std::memcpy(out + 12, &colours[i], 4);
    out += kPointStep;
  }
  return cloud;
}

std::vector<CloudPoint> from_point_cloud2(const sensor_msgs::msg::PointCloud2& cloud) {
  if (cloud.is_bigendian()) throw std::invalid_argument("big-endian PointCloud2 is not supported");
  const int x = float_offset(cloud, "x"), y = float_offset(cloud, "y"), z = float_offset(cloud, "z");
  if (x < 0 || y < 0 || z < 0) throw std::invalid_argument("PointCloud2 lacks an x, y or z field");
  const int intensity = float_offset(cloud, "intensity");
  const size_t count = size_t{cloud.width()} * cloud.height();
  if (cloud.row_step() < size_t{cloud.width()} * cloud.point_step() ||
      cloud.data().size() < size_t{cloud.row_step()} * cloud.height())
    throw std::invalid_argument("PointCloud2 data is shorter than width x height x point_step");
  std::vector<CloudPoint> points;
  if (x == 0 && y == 4 && z == 8 && intensity == 12 && cloud.point_step() == kPointStep &&
      cloud.row_step() == size_t{cloud.width()} * kPointStep) {
    // scanbus's own layout (to_point_cloud2): fixed offsets, no per-field lookups.
    points.resize(count);
    const uint8_t* in = cloud.data().data();
    for (auto& point : points) {
      std::memcpy(point.position.data(), in, 12);
      std::memcpy(&point.intensity, in + 12, 4);
      in += kPointStep;
    }
    return points;
  }
  points.reserve(count);
  auto read = [](const uint8_t* at) {
    float value;
    std::memcpy(&value, at, 4);
    return value;
  };
  for (uint32_t row = 0; row < cloud.height(); ++row) {
    for (uint32_t column = 0; column < cloud.width(); ++column) {
      const uint8_t* point = cloud.data().data() + size_t{row} * cloud.row_step() + size_t{column} * cloud.point_step();
      points.push_back(
          {{read(point + x), read(point + y), read(point + z)}, intensity < 0 ? 0.f : read(point + intensity)});
    }
  }
  return points;
}

}  // namespace scanbus

#include "scanbus/geometry_message.hpp"

namespace scanbus {

Eigen::Quaterniond to_eigen(const geometry_msgs::msg::Quaternion& q) { return {q.w(), q.x(), q.y(), q.z()}; }

Eigen::Vector3d to_eigen(const geometry_msgs::msg::Point& p) { return {p.x(), p.y(), p.z()}; }

Eigen::Isometry3d to_eigen(const geometry_msgs::msg::Transform& t) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translation() = Eigen::Vector3d(t.translation().x(), t.translation().y(), t.translation().z());
  result.linear() = to_eigen(t.rotation()).normalized().toRotationMatrix();
  return result;
}

Eigen::Isometry3d to_eigen(const geometry_msgs::msg::Pose& p) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translation() = to_eigen(p.position());
  result.linear() = to_eigen(p.orientation()).normalized().toRotationMatrix();
  return result;
}

geometry_msgs::msg::Quaternion to_quaternion_message(const Eigen::Quaterniond& q) {
  geometry_msgs::msg::Quaternion message;
  message.x(q.x());
  message.y(q.y());
  message.z(q.z());
  message.w(q.w());
  return message;
}

geometry_msgs::msg::Point to_point_message(const Eigen::Vector3d& p) {
  geometry_msgs::msg::Point message;
  message.x(p.x());
  message.y(p.y());
  message.z(p.z());
  return message;
}

geometry_msgs::msg::Pose to_pose_message(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation) {
  geometry_msgs::msg::Pose message;
  message.position(to_point_message(position));
  message.orientation(to_quaternion_message(orientation));
  return message;
}

geometry_msgs::msg::Transform to_transform_message(const Eigen::Isometry3d& t) {
  geometry_msgs::msg::Transform message;
  message.translation().x(t.translation().x());
  message.translation().y(t.translation().y());
  message.translation().z(t.translation().z());
  message.rotation(to_quaternion_message(Eigen::Quaterniond(t.linear())));
  return message;
}

}  // namespace scanbus

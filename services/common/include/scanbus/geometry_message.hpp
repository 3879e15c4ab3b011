// Eigen to and from geometry_msgs, both ways beside each other: every node and reader
// converts here. The wire's quaternion is x y z w; Eigen's constructor takes w first.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "scanbus_msgs/Pose.h"
#include "scanbus_msgs/Transform.h"

namespace scanbus {

// As sent (not normalised: a receiver checks what it was given).
Eigen::Quaterniond to_eigen(const geometry_msgs::msg::Quaternion& q);
Eigen::Vector3d to_eigen(const geometry_msgs::msg::Point& p);
// The rotation normalised: a transform is a rigid motion whatever rounding the sender did.
Eigen::Isometry3d to_eigen(const geometry_msgs::msg::Transform& t);
Eigen::Isometry3d to_eigen(const geometry_msgs::msg::Pose& p);  // likewise

geometry_msgs::msg::Quaternion to_quaternion_message(const Eigen::Quaterniond& q);
geometry_msgs::msg::Point to_point_message(const Eigen::Vector3d& p);
geometry_msgs::msg::Pose to_pose_message(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation);
geometry_msgs::msg::Transform to_transform_message(const Eigen::Isometry3d& t);

}  // namespace scanbus

#include "scanbus/geometry_message.hpp"

#include <gtest/gtest.h>

using namespace scanbus;

namespace {

const Eigen::Quaterniond kTurn = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()));

}  // namespace

TEST(GeometryMessage, QuaternionsKeepTheirOrderOnTheWire) {
  const auto message = to_quaternion_message(kTurn);
  EXPECT_EQ(message.w(), kTurn.w());  // not x: Eigen stores x y z w, its constructor takes w first
  EXPECT_EQ(message.x(), kTurn.x());
  EXPECT_TRUE(to_eigen(message).coeffs().isApprox(kTurn.coeffs(), 0));
}

TEST(GeometryMessage, APoseSurvivesTheWire) {
  const Eigen::Vector3d position(1.5, -2.25, 30);
  const auto message = to_pose_message(position, kTurn);
  EXPECT_EQ(to_eigen(message.position()), position);
  EXPECT_TRUE(to_eigen(message.orientation()).isApprox(kTurn, 0));
  const Eigen::Isometry3d pose = to_eigen(message);  // as a transform of the body in its frame
  EXPECT_EQ(pose.translation(), position);
  EXPECT_TRUE(pose.linear().isApprox(kTurn.toRotationMatrix(), 1e-12));
}

TEST(GeometryMessage, ATransformSurvivesTheWire) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translate(Eigen::Vector3d(0.1, 0.2, -0.3)).rotate(kTurn);
  EXPECT_TRUE(to_eigen(to_transform_message(t)).isApprox(t, 1e-12));
}

TEST(GeometryMessage, AReceivedTransformIsRigid) {
  geometry_msgs::msg::Transform message;
  message.rotation().w(2);  // not a unit quaternion: rounding, or a sender's mistake
  const Eigen::Isometry3d t = to_eigen(message);
  EXPECT_TRUE(t.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

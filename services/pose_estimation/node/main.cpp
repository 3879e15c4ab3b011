#include "pose_estimation_node.hpp"

int main(int argc, char** argv) {
  return scanbus::service_main("pose_estimation", argc, argv, scanbus::pose_estimation::make_pose_estimation);
}

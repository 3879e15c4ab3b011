#include "sensor_replay_node.hpp"

int main(int argc, char** argv) {
  return scanbus::service_main("sensor_replay", argc, argv, scanbus::sensor_replay::make_sensor_replay);
}

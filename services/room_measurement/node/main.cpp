#include "room_measurement_node.hpp"

int main(int argc, char** argv) {
  return scanbus::service_main("room_measurement", argc, argv, scanbus::room_measurement::make_room_measurement);
}

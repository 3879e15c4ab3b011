#include "foxglove_bridge_node.hpp"

int main(int argc, char** argv) {
  return scanbus::service_main("foxglove_bridge", argc, argv, scanbus::foxglove_bridge::make_foxglove_bridge);
}

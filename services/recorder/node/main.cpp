#include "recorder_node.hpp"

int main(int argc, char** argv) {
  return scanbus::service_main("recorder", argc, argv, scanbus::recorder::make_recorder);
}

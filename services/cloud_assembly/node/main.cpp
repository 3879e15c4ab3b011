#include "cloud_assembly_node.hpp"

int main(int argc, char** argv) {
  return scanbus::service_main("cloud_assembly", argc, argv, scanbus::cloud_assembly::make_cloud_assembly);
}

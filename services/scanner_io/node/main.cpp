#include "scanner_io_node.hpp"

int main(int argc, char** argv) {
  return scanbus::service_main("scanner_io", argc, argv, scanbus::scanner_io::make_scanner_io);
}

#include "scan_matcher_node.hpp"

int main(int argc, char** argv) {
  return scanbus::service_main("scan_matcher", argc, argv, scanbus::scan_matcher::make_scan_matcher);
}

// Laser logs as MCAP recordings of LaserScan messages on /scan (header stamp = the log's
// timestamp, which relation files name): what `scanbus scanmatch convert` writes and
// `scanbus scanmatch eval --log F.mcap` reads. Wheel odometry has no message here and is
// not carried.
#pragma once

#include <string>
#include <vector>

#include "scanbus/scan_matcher/laser_log.hpp"

namespace scanbus::scan_matcher {

void write_laser_mcap(const std::string& path, const std::vector<LaserRecord>& records, const std::string& frame);
// Throws LogError naming the file and the problem (MCAP damage, no /scan messages).
std::vector<LaserRecord> read_laser_mcap(const std::string& path);
// By extension: .mcap as above, anything else a CARMEN log.
std::vector<LaserRecord> load_laser_log(const std::string& path);

}  // namespace scanbus::scan_matcher

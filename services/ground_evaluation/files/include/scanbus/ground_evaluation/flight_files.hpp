// What a scored flight leaves for a person to look at and plot (`scanbus eval mav --out`).
#pragma once

#include <string>

#include "scanbus/ground_evaluation/flight_evaluation.hpp"
#include "scanbus/sensor_replay/mav_log.hpp"

namespace scanbus::ground_evaluation {

// Into `folder`, named after `flight` (spaces as '_', any folder part dropped: "scenario IV"
// gives scenario_IV_...): _heights.csv (truth, the four heights, the scan's ground clearance
// and the fused height's sigma at every pose), _<source>.pcd and .png (the cloud built with
// each height, coloured by height from above), _fused_dem.tif (the fused cloud's elevation
// grid, georeferenced from the log's META origin). Throws std::runtime_error naming a file
// that cannot be written, sensor_replay::MavLogError when the log has no origin.
void write_flight_files(const std::string& folder, const std::string& flight, const FlightEvaluation& evaluation,
                        const sensor_replay::MavLog& log);

}  // namespace scanbus::ground_evaluation

// The scanner's logic, independent of the board: commands, speed control, the pitch
// schedule, revolution counting from the encoder, and measurement lines.
#ifndef SCANBUS_FIRMWARE_SCANNER_CORE_H
#define SCANBUS_FIRMWARE_SCANNER_CORE_H

#include <stdint.h>

#include "hal.h"
#include "protocol.h"

namespace scanner {

// Gear train (thesis 4.1.2): encoder 3 counts per motor turn, gearbox 42.875:1, then
// 15/50 to the pole: 428.75 = 1715/4 counts per pole revolution, 0.8397 degrees a count.
const int32_t kQuarterCountsPerRevolution = 1715;
// Yaw of an encoder count in hundredths of a degree, exact: 343 counts are 288 degrees.
uint32_t yaw_centidegrees(uint32_t counts);
// Yaw travelled `elapsed_us` after a count edge, at `counts_per_period` counts per 250 ms
// control period, in hundredths of a degree; at most one count's worth.
uint32_t yaw_since_edge_centidegrees(uint32_t elapsed_us, uint32_t counts_per_period);

// Table 4.2 speed settings.
const uint8_t kResolutions = 3;
uint8_t rpm_of_resolution(uint8_t resolution);

// Pitch schedule (thesis 4.1.3): 42 degrees up to 123 in 3 degree steps, one step per
// revolution; each new scan cycle starts one degree later, modulo the step (eq. 4.9).
const uint8_t kPitchStartDegrees = 42;
const uint8_t kPitchStepDegrees = 3;
const uint8_t kRevolutionsPerScan = 27;
uint8_t pitch_degrees(uint8_t revolution, uint16_t cycle);

enum State : uint8_t { kIdle = 1, kScanning = 2 };
enum ErrorCode : uint8_t { kUnknownCommand = 1, kBadArgument = 2, kBusy = 3, kLidarNoAnswer = 4, kLineTooLong = 5 };

class ScannerCore {
 public:
  explicit ScannerCore(Hal& hal) : hal_(hal) {}

  void begin();  // says hello
  void poll();   // call as often as possible from the main loop

  State state() const { return state_; }
  uint8_t resolution() const { return resolution_; }
  uint8_t revolution() const { return revolution_; }
  uint16_t cycle() const { return cycle_; }
  uint32_t sequence() const { return sequence_; }
  uint8_t motor_duty() const { return static_cast<uint8_t>(duty16_ >> 4); }
  uint16_t measured_rpm_x10() const { return rpm_x10_; }

 private:
  void read_commands();
  void execute(const char* command);
  void start();
  void stop();
  void control_speed(uint32_t now);
  void track_revolution(int32_t count, uint32_t now_ms);
  void measure();
  void send_hello();
  void send_status();
  void send_error(ErrorCode code, const char* word);
  void send_fields(char tag, const uint32_t* fields, int count);

  Hal& hal_;
  State state_ = kIdle;
  uint8_t resolution_ = 1;
  uint8_t revolution_ = 0;
  uint16_t cycle_ = 0;
  uint32_t sequence_ = 0;
  int32_t revolution_end_q_ = 0;     // quarter counts at which the current revolution ends
  bool revolution_pending_ = false;  // the next revolution starts with its first measurement
  uint32_t settle_until_ = 0;        // ms: no measurements while the servo moves
  uint16_t duty16_ = 0;              // motor duty in 1/16 steps, for a smooth integral controller
  uint32_t control_time_ = 0;
  int32_t control_count_ = 0;
  uint16_t rpm_x10_ = 0;
  uint32_t counts_per_period_ = 0;
  uint32_t last_lidar_error_ = 0;
  char command_[24];
  uint8_t command_length_ = 0;
  bool command_overflow_ = false;
};

}  // namespace scanner

#endif

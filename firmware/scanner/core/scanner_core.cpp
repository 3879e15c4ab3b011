#include "scanner_core.h"

#include <string.h>

namespace scanner {

namespace {

const uint32_t kControlPeriodMs = 250;
const uint32_t kServoSettleMs = 80;
// No measurements while the pole spins up: the speed the yaw interpolation uses is stale.
const uint32_t kSpinUpMs = 500;
const uint32_t kLidarErrorEveryMs = 1000;
// Pole speed at full duty: 350 RPM gearbox output through 15/50.
const uint16_t kFullDutyRpm = 105;

}  // namespace

uint32_t yaw_centidegrees(uint32_t counts) {
  // Split so 32-bit arithmetic never overflows (no 64-bit maths on the AVR).
  return (counts / 343) * 28800UL + (counts % 343) * 28800UL / 343;
}

uint32_t yaw_since_edge_centidegrees(uint32_t elapsed_us, uint32_t counts_per_period) {
  const uint32_t one_count = 84;         // 83.97 rounded up: never past the next edge's yaw
  if (elapsed_us > 1000000UL) return 0;  // stalled: no speed to trust
  // counts = elapsed_us * counts_per_period / 250000, in units of 1/1000 count, in 32 bits.
  const uint32_t milli_counts = elapsed_us / 10 * counts_per_period / 25;
  const uint32_t yaw = milli_counts * 288UL / 343 / 10;  // 343 counts = 28800 cdeg
  return yaw < one_count ? yaw : one_count - 1;
}

uint8_t rpm_of_resolution(uint8_t resolution) {
  static const uint8_t kRpm[kResolutions] = {12, 20, 28};
  return kRpm[resolution < kResolutions ? resolution : kResolutions - 1];
}

uint8_t pitch_degrees(uint8_t revolution, uint16_t cycle) {
  return static_cast<uint8_t>(kPitchStartDegrees + cycle % kPitchStepDegrees + revolution * kPitchStepDegrees);
}

void ScannerCore::begin() {
  hal_.set_motor(0);
  hal_.set_servo_degrees(pitch_degrees(0, cycle_));
  send_hello();
}

void ScannerCore::poll() {
  read_commands();
  if (state_ != kScanning) return;
  const uint32_t now = hal_.millis();
  control_speed(now);
  if (!revolution_pending_) track_revolution(hal_.encoder_count(), now);
  if (state_ != kScanning || static_cast<int32_t>(now - settle_until_) < 0) return;
  // A revolution counts from the first measurement at its pitch, so each one holds a full
  // 360 degrees of data and the servo's settling gap moves around instead of blanking
  // the same wedge every time.
  if (revolution_pending_) {
    revolution_end_q_ = hal_.encoder_count() * 4 + kQuarterCountsPerRevolution;
    revolution_pending_ = false;
  }
  measure();  // the LiDAR is the rate limit, about 50 Hz
}

void ScannerCore::read_commands() {
  for (int byte = hal_.read(); byte >= 0; byte = hal_.read()) {
    if (byte == '\r') continue;
    if (byte != '\n') {
      if (command_length_ + 1u < sizeof(command_)) {
        command_[command_length_++] = static_cast<char>(byte);
      } else {
        command_overflow_ = true;
      }
      continue;
    }
    command_[command_length_] = '\0';
    if (command_overflow_) {
      send_error(kLineTooLong, "line-too-long");
    } else if (command_length_ > 0) {
      execute(command_);
    }
    command_length_ = 0;
    command_overflow_ = false;
  }
}

void ScannerCore::execute(const char* command) {
  if (strcmp(command, "START") == 0) {
    if (state_ == kScanning) return send_error(kBusy, "busy");
    start();
  } else if (strcmp(command, "STOP") == 0) {
    stop();
    send_status();
  } else if (strcmp(command, "STATUS") == 0) {
    send_status();
  } else if (strcmp(command, "HELLO") == 0) {
    send_hello();
  } else if (strncmp(command, "RES ", 4) == 0) {
    const char* argument = command + 4;
    if (state_ == kScanning) return send_error(kBusy, "busy");
    if (argument[0] < '0' || argument[0] >= '0' + kResolutions || argument[1] != '\0')
      return send_error(kBadArgument, "bad-argument");
    resolution_ = static_cast<uint8_t>(argument[0] - '0');
    send_status();
  } else {
    send_error(kUnknownCommand, "unknown-command");
  }
}

void ScannerCore::start() {
  state_ = kScanning;
  revolution_ = 0;
  revolution_pending_ = true;
  control_count_ = hal_.encoder_count();
  control_time_ = hal_.millis();
  settle_until_ = control_time_ + kSpinUpMs;
  duty16_ = static_cast<uint16_t>(rpm_of_resolution(resolution_) * 255U * 16U / kFullDutyRpm);
  hal_.set_servo_degrees(pitch_degrees(0, cycle_));
  hal_.set_motor(motor_duty());
  send_status();
}

void ScannerCore::stop() {
  state_ = kIdle;
  duty16_ = 0;
  hal_.set_motor(0);
  rpm_x10_ = 0;
}

void ScannerCore::control_speed(uint32_t now) {
  // Acquisitions block for ~20 ms, so a period runs somewhat over: use its true length.
  const uint32_t elapsed = now - control_time_;
  if (elapsed < kControlPeriodMs) return;
  const int32_t count = hal_.encoder_count();
  const int32_t seen = 4 * (count - control_count_);  // quarter counts
  const int32_t target =
      static_cast<int32_t>(rpm_of_resolution(resolution_) * kQuarterCountsPerRevolution * elapsed / 60000UL);
  counts_per_period_ = seen > 0 ? static_cast<uint32_t>(seen) * kControlPeriodMs / (4 * elapsed) : 0;
  rpm_x10_ =
      seen > 0 ? static_cast<uint16_t>(static_cast<uint32_t>(seen) * 600000UL / (kQuarterCountsPerRevolution * elapsed))
               : 0;
  int32_t duty16 = static_cast<int32_t>(duty16_) + (target - seen) * 4;
  if (duty16 < 16) duty16 = 16;
  if (duty16 > 255 * 16) duty16 = 255 * 16;
  duty16_ = static_cast<uint16_t>(duty16);
  hal_.set_motor(motor_duty());
  control_time_ = now;
  control_count_ = count;
}

void ScannerCore::track_revolution(int32_t count, uint32_t now_ms) {
  if (count * 4 < revolution_end_q_) return;
  const uint32_t lap[] = {revolution_, static_cast<uint32_t>(pitch_degrees(revolution_, cycle_)) * 100U};
  send_fields('L', lap, 2);
  revolution_pending_ = true;
  if (++revolution_ < kRevolutionsPerScan) {
    hal_.set_servo_degrees(pitch_degrees(revolution_, cycle_));
    settle_until_ = now_ms + kServoSettleMs;
    return;
  }
  const uint32_t done[] = {cycle_, kRevolutionsPerScan};
  send_fields('D', done, 2);
  stop();
  ++cycle_;
}

void ScannerCore::measure() {
  // The yaw at the start of the acquisition: last edge plus the turn since.
  const uint32_t start_us = hal_.micros();
  const int32_t count = hal_.encoder_count();
  const uint32_t yaw = yaw_centidegrees(static_cast<uint32_t>(count)) +
                       yaw_since_edge_centidegrees(start_us - hal_.encoder_edge_micros(), counts_per_period_);
  uint16_t range_cm = 0;
  uint8_t signal = 0;
  if (!hal_.measure(range_cm, signal)) {
    const uint32_t now = hal_.millis();
    if (now - last_lidar_error_ >= kLidarErrorEveryMs) {
      send_error(kLidarNoAnswer, "lidar-no-answer");
      last_lidar_error_ = now;
    }
    return;
  }
  const uint32_t fields[] = {sequence_++, yaw, static_cast<uint32_t>(pitch_degrees(revolution_, cycle_)) * 100U,
                             range_cm, signal};
  send_fields('M', fields, 5);
}

void ScannerCore::send_hello() {
  char line[kMaxLine];
  int length = 0;
  const char* prefix = "H scanbus-scanner ";
  for (const char* c = prefix; *c; ++c) line[length++] = *c;
  length += format_unsigned(line + length, kProtocolVersion);
  line[length++] = ' ';
  for (const char* c = kFirmwareVersion; *c; ++c) line[length++] = *c;
  finish_line(line, length);
  hal_.write(line);
}

void ScannerCore::send_status() {
  const uint32_t fields[] = {state_, resolution_, rpm_x10_, revolution_, sequence_, cycle_};
  send_fields('S', fields, 6);
}

void ScannerCore::send_error(ErrorCode code, const char* word) {
  char line[kMaxLine];
  int length = 0;
  line[length++] = 'E';
  line[length++] = ' ';
  length += format_unsigned(line + length, code);
  line[length++] = ' ';
  for (const char* c = word; *c && length < kMaxLine - 5; ++c) line[length++] = *c;
  finish_line(line, length);
  hal_.write(line);
}

void ScannerCore::send_fields(char tag, const uint32_t* fields, int count) {
  char line[kMaxLine];
  format_fields(line, tag, fields, count);
  hal_.write(line);
}

}  // namespace scanner

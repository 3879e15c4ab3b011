// What the scanner core needs from the hardware. The Arduino sketch implements it with
// Wire, Timer1 and interrupts; the host simulator with a physics model and a pty.
#ifndef SCANBUS_FIRMWARE_HAL_H
#define SCANBUS_FIRMWARE_HAL_H

#include <stdint.h>

namespace scanner {

class Hal {
 public:
  virtual ~Hal() {}
  virtual uint32_t millis() = 0;
  virtual uint32_t micros() = 0;
  // Quadrature counts of the motor's encoder since boot, and the time of the last count
  // (both kept by the encoder ISR, read atomically).
  virtual int32_t encoder_count() = 0;
  virtual uint32_t encoder_edge_micros() = 0;
  // Motor duty 0..255 in the turning direction; 0 stops.
  virtual void set_motor(uint8_t duty) = 0;
  virtual void set_servo_degrees(uint8_t degrees) = 0;
  // One LIDAR-Lite v3 acquisition; false when the sensor did not answer.
  virtual bool measure(uint16_t& range_cm, uint8_t& signal) = 0;
  virtual void write(const char* text) = 0;
  // Next byte from the host, or -1 when none is waiting.
  virtual int read() = 0;
};

}  // namespace scanner

#endif

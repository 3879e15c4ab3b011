// Arduino Uno firmware of the rotating LiDAR scanner (room thesis, chapter 4): the
// portable ScannerCore on the board's hardware. Builds with Debian's arduino-core-avr and
// arduino-mk; no third-party libraries.
//
// Wiring (Adafruit Motor Shield v2 stacked on the Uno):
//   LIDAR-Lite v3   I2C, address 0x62
//   PCA9685         I2C, address 0x60 (the shield); DC motor on M1
//   pitch servo     pin 10 (the shield's "Servo 1" header), Timer1 PWM
//   Hall encoder    channels A and B on pins 2 and 3 (INT0, INT1)
#include <Arduino.h>
#include <Wire.h>

#include "protocol.h"
#include "scanner_core.h"

namespace {

const uint8_t kLidarAddress = 0x62;
const uint8_t kMotorShieldAddress = 0x60;
const uint8_t kEncoderA = 2;
const uint8_t kEncoderB = 3;

// Quadrature decoding on every edge of both channels (noise on one channel cancels out);
// one count per full cycle, 3 per motor turn as the thesis's gear arithmetic assumes.
volatile int32_t quarter_steps = 0;
volatile uint32_t edge_micros = 0;
volatile uint8_t encoder_state = 0;

void on_encoder_edge() {
  // Gray-code transition table: +1 forward, -1 backward, 0 invalid or no change.
  static const int8_t kStep[16] = {0, 1, -1, 0, -1, 0, 0, 1, 1, 0, 0, -1, 0, -1, 1, 0};
  const uint8_t state = static_cast<uint8_t>((digitalRead(kEncoderA) << 1) | digitalRead(kEncoderB));
  const int8_t step = kStep[(encoder_state << 2) | state];
  encoder_state = state;
  if (step == 0) return;
  quarter_steps += step;
  if ((quarter_steps & 3) == 0) edge_micros = micros();
}

// PCA9685: 12-bit PWM at 1.6 kHz for the motor driver's inputs.
void pca9685_write(uint8_t reg, uint8_t value) {
  Wire.beginTransmission(kMotorShieldAddress);
  Wire.write(reg);
  Wire.write(value);
  Wire.endTransmission();
}

void pca9685_channel(uint8_t channel, uint16_t on, uint16_t off) {
  Wire.beginTransmission(kMotorShieldAddress);
  Wire.write(static_cast<uint8_t>(0x06 + 4 * channel));
  Wire.write(on & 0xFF);
  Wire.write(on >> 8);
  Wire.write(off & 0xFF);
  Wire.write(off >> 8);
  Wire.endTransmission();
}

void pca9685_begin() {
  pca9685_write(0x00, 0x10);  // MODE1: sleep, to set the prescaler
  pca9685_write(0xFE, 3);     // 25 MHz / (4096 * (3 + 1)) = 1.5 kHz
  pca9685_write(0x00, 0x20);  // awake, register auto-increment
  delay(1);
}

class BoardHal : public scanner::Hal {
 public:
  void begin() {
    Serial.begin(115200);
    Wire.begin();
    Wire.setClock(400000);
    Wire.setWireTimeout(3000, true);  // a hung I2C bus must not hang the scanner
    pca9685_begin();
    pinMode(kEncoderA, INPUT_PULLUP);
    pinMode(kEncoderB, INPUT_PULLUP);
    attachInterrupt(digitalPinToInterrupt(kEncoderA), on_encoder_edge, CHANGE);
    attachInterrupt(digitalPinToInterrupt(kEncoderB), on_encoder_edge, CHANGE);
    // Servo on OC1B (pin 10): Timer1 fast PWM, TOP = ICR1, 0.5 us ticks, 20 ms period.
    // Debian does not package Arduino's Servo library; the hardware timer is also jitter-free.
    pinMode(10, OUTPUT);
    TCCR1A = _BV(COM1B1) | _BV(WGM11);
    TCCR1B = _BV(WGM13) | _BV(WGM12) | _BV(CS11);
    ICR1 = 39999;
  }

  uint32_t millis() override { return ::millis(); }
  uint32_t micros() override { return ::micros(); }

  int32_t encoder_count() override {
    noInterrupts();
    const int32_t steps = quarter_steps;
    interrupts();
    return steps >> 2;  // arithmetic shift: floor division by 4
  }

  uint32_t encoder_edge_micros() override {
    noInterrupts();
    const uint32_t at = edge_micros;
    interrupts();
    return at;
  }

  void set_motor(uint8_t duty) override {
    // M1 on the shield: PWM channel 8, IN2 channel 9, IN1 channel 10; forward = IN1 high.
    pca9685_channel(10, duty ? 4096 : 0, duty ? 0 : 4096);
    pca9685_channel(9, 0, 4096);
    pca9685_channel(8, 0, static_cast<uint16_t>(duty) * 16);
  }

  void set_servo_degrees(uint8_t degrees) override {
    // 544..2400 us for 0..180 degrees, the pulse range Arduino's Servo library uses.
    const uint32_t pulse_us = 544UL + (2400UL - 544UL) * (degrees > 180 ? 180 : degrees) / 180;
    OCR1B = static_cast<uint16_t>(pulse_us * 2);
  }

  bool measure(uint16_t& range_cm, uint8_t& signal) override {
    if (!lidar_write(0x00, 0x04)) return false;  // acquire with receiver bias correction
    const uint32_t started = ::millis();
    uint8_t status = 1;
    do {
      if (!lidar_read(0x01, &status, 1) || ::millis() - started > 25) return false;
    } while (status & 0x01);  // busy
    uint8_t distance[2];
    if (!lidar_read(0x8F, distance, 2)) return false;  // 0x0f/0x10 with auto-increment
    range_cm = static_cast<uint16_t>((distance[0] << 8) | distance[1]);
    return lidar_read(0x0E, &signal, 1);  // peak signal strength
  }

  void write(const char* text) override { Serial.print(text); }
  int read() override { return Serial.read(); }

 private:
  static bool lidar_write(uint8_t reg, uint8_t value) {
    Wire.beginTransmission(kLidarAddress);
    Wire.write(reg);
    Wire.write(value);
    return Wire.endTransmission() == 0;
  }

  static bool lidar_read(uint8_t reg, uint8_t* out, uint8_t count) {
    Wire.beginTransmission(kLidarAddress);
    Wire.write(reg);
    if (Wire.endTransmission() != 0) return false;
    if (Wire.requestFrom(kLidarAddress, count) != count) return false;
    for (uint8_t i = 0; i < count; ++i) out[i] = static_cast<uint8_t>(Wire.read());
    return true;
  }
};

BoardHal board;
scanner::ScannerCore core(board);

}  // namespace

void setup() {
  board.begin();
  core.begin();
}

void loop() { core.poll(); }

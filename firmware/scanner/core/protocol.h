// The scanner's line protocol (firmware/PROTOCOL.md): formatting on the device side and
// the checksum both sides compute.
#ifndef SCANBUS_FIRMWARE_PROTOCOL_H
#define SCANBUS_FIRMWARE_PROTOCOL_H

#include <stdint.h>

namespace scanner {

const int kProtocolVersion = 1;
const char* const kFirmwareVersion = "0.1.0";
const int kMaxLine = 64;

// XOR of every byte of the payload (what stands between the start and '*').
uint8_t checksum(const char* payload, int length);

// Appends "*HH\n" to the payload in `line` (capacity kMaxLine); returns the total length.
int finish_line(char* line, int length);

// Writes an unsigned decimal into `out`; returns the number of characters.
int format_unsigned(char* out, uint32_t value);

// Builds "<tag> v1 v2 ...*HH\n" from up to 6 unsigned fields.
int format_fields(char* line, char tag, const uint32_t* fields, int count);

}  // namespace scanner

#endif

#include "protocol.h"

namespace scanner {

uint8_t checksum(const char* payload, int length) {
  uint8_t sum = 0;
  for (int i = 0; i < length; ++i) sum ^= static_cast<uint8_t>(payload[i]);
  return sum;
}

int finish_line(char* line, int length) {
  static const char kHex[] = "0123456789ABCDEF";
  const uint8_t sum = checksum(line, length);
  line[length++] = '*';
  line[length++] = kHex[sum >> 4];
  line[length++] = kHex[sum & 0x0F];
  line[length++] = '\n';
  line[length] = '\0';
  return length;
}

int format_unsigned(char* out, uint32_t value) {
  char digits[10];
  int count = 0;
  do {
    digits[count++] = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0);
  for (int i = 0; i < count; ++i) out[i] = digits[count - 1 - i];
  return count;
}

int format_fields(char* line, char tag, const uint32_t* fields, int count) {
  int length = 0;
  line[length++] = tag;
  for (int i = 0; i < count; ++i) {
    line[length++] = ' ';
    length += format_unsigned(line + length, fields[i]);
  }
  return finish_line(line, length);
}

}  // namespace scanner

// MCAP files as `scanbus replay` and `scanbus info` read them: summary, every message, and
// again in salvage mode (messages up to the damage).
#include "fuzz_input.hpp"
#include "scanbus/recorder/mcap_reader.hpp"

using scanbus::recorder::McapChannel;
using scanbus::recorder::McapError;
using scanbus::recorder::McapMessage;
using scanbus::recorder::McapReader;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const scanbus::fuzz::InputFile file(data, size, "mcap");
  size_t bytes = 0;
  const auto count = [&](const McapMessage& message, const McapChannel&) { bytes += message.size; };
  try {
    McapReader reader(file.path());
    reader.read_summary();
    reader.read_messages(count);
  } catch (const McapError&) {
  }
  try {
    McapReader reader(file.path());
    reader.read_messages(count, true);
  } catch (const McapError&) {
  }
  scanbus::fuzz::require(bytes <= 2 * size + 64 * 1024 * 1024);  // decompression stays bounded
  return 0;
}

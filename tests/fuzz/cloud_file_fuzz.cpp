// Cloud files as `scanbus eval boxes` and `scanbus cloud render` read them: the first byte
// picks PCD, PLY or XYZ text (by the extension, as read_cloud does), the rest is the file.
#include "fuzz_input.hpp"
#include "scanbus/cloud_io/cloud_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {"pcd", "ply", "xyz"};
  const scanbus::fuzz::InputFile file(data + 1, size - 1, kExtensions[data[0] % 3]);
  try {
    scanbus::cloud_io::read_cloud(file.path(), 1.0);
  } catch (const scanbus::cloud_io::CloudFileError&) {
  }
  return 0;
}

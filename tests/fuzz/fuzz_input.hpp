// Helpers for the fuzz targets (tests/fuzz/README.md).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace scanbus::fuzz {

// The input as a file, for parsers that take a path (PCL's readers, the MCAP reader's
// FILE*): one per process in /dev/shm (TMPDIR when that is missing), removed afterwards.
class InputFile {
 public:
  InputFile(const uint8_t* data, size_t size, const std::string& extension) {
    const char* folder =
        access("/dev/shm", W_OK) == 0 ? "/dev/shm" : (std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp");
    path_ = std::string(folder) + "/scanbus_fuzz_" + std::to_string(getpid()) + "." + extension;
    std::FILE* file = std::fopen(path_.c_str(), "wb");
    if (!file || std::fwrite(data, 1, size, file) != size || std::fclose(file) != 0) std::abort();
  }
  ~InputFile() { std::remove(path_.c_str()); }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// A broken invariant: abort, so libFuzzer keeps the input (a plain assert vanishes under NDEBUG).
inline void require(bool holds) {
  if (!holds) std::abort();
}

}  // namespace scanbus::fuzz

// Writes an FMU archive (a zip, libzip): files given by content or by path, written to
// a temporary file beside the target and renamed over it only when complete, so an
// error never leaves a half-written .fmu.
#pragma once
#include <map>
#include <string>

namespace packsim {

struct FmuArchive {
  std::map<std::string, std::string> contents;  // path in the archive -> bytes
  std::map<std::string, std::string> files;     // path in the archive -> file on disk
};

// Throws std::runtime_error naming the output file and libzip's reason.
void writeFmuArchive(const FmuArchive& a, const std::string& outPath);

}  // namespace packsim

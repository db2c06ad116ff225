#include "text_file_kind.hpp"

#include <cstring>

namespace packsim {

namespace {

bool startsWith(const std::string& bytes, const char* magic, size_t n) {
  return bytes.size() >= n && std::memcmp(bytes.data(), magic, n) == 0;
}

}  // namespace

std::string notYamlText(const std::string& bytes) {
  // The formats packsim itself writes or loads, by their signatures.
  if (startsWith(bytes, "\x89HDF\r\n\x1a\n", 8))
    return "an HDF5 file (a packsim result?), not a scenario, which is YAML text: read a result with "
           "`packsim report FILE`, `packsim export FILE` or packsim.load(FILE) in Python";
  if (startsWith(bytes, "PK\x03\x04", 4)) return "a ZIP archive (an FMU?), not a scenario, which is YAML text";
  if (startsWith(bytes, "\x7f" "ELF", 4))
    return "an executable or shared library (a firmware?), not a scenario, which is YAML text: a firmware "
           "library goes under bms.firmware.library in a scenario";
  const size_t head = bytes.size() < 8192 ? bytes.size() : 8192;
  const void* nul = std::memchr(bytes.data(), '\0', head);
  if (nul != nullptr)
    return "binary data (a NUL byte at byte " +
           std::to_string(static_cast<const char*>(nul) - bytes.data() + 1) + "), not a scenario, which is YAML text";
  return "";
}

}  // namespace packsim

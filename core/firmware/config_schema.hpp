// A firmware's configuration schema (bms/packsim_fw.h psfw_config_schema): the fields
// of the blob its init receives, read without running firmware code -- from a host
// library's exported table, or from a target ELF's flash -- and checked, so the loader
// can check `bms.firmware.config` against it and build the blob in its order
// (core/scenario/load_firmware.cpp).
#pragma once
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace packsim {

struct ElfImage;

struct ConfigField {
  std::string name, unit, doc;
  bool real = false;   // PSFW_CONFIG_FLOAT32 (else INT32)
  uint32_t count = 1;  // 1: a number; n > 1: a list of n
  double min = 0.0, max = 0.0, def = 0.0;
};

struct ConfigSchema {
  std::vector<ConfigField> fields;
  size_t blobBytes() const;  // 4 bytes per number
};

// A schema the firmware exports but that breaks its rules (what: which field, which rule).
class ConfigSchemaError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The schema a host library exports (dlopen, dlsym; the read runs under the fault
// guard). nullopt when it exports none, or when the library cannot be opened (the run
// then reports why, as without a schema). Throws ConfigSchemaError.
std::optional<ConfigSchema> readLibraryConfigSchema(const std::string& path);

// The schema in a target ELF (its symbol's bytes in the ELF's flash image, pointers as
// the Cortex-M4's 32-bit addresses). nullopt when the ELF has no such symbol. Throws
// ConfigSchemaError.
std::optional<ConfigSchema> readElfConfigSchema(const ElfImage& elf);

}  // namespace packsim

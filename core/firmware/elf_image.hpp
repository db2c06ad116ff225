// A firmware ELF for the virtual Cortex-M4 (bms.firmware.target: cortex-m4): its
// loadable segments and its symbols, read with the system's <elf.h> layouts (an ELF32
// little-endian ARM executable as arm-none-eabi-ld writes it). Everything is checked
// when the scenario loads: a file that is not such an ELF, or lacks a symbol the
// virtual board needs, throws ElfError naming the file and the field.
#pragma once
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace packsim {

class ElfError : public std::runtime_error {
 public:
  ElfError(const std::string& file, const std::string& field, const std::string& what)
      : std::runtime_error(file + ": " + field + ": " + what), field_(field) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

struct ElfSegment {
  uint32_t vaddr = 0;          // where it runs (flash for code, RAM for initialised data)
  uint32_t memsz = 0;          // bytes in memory; those past bytes.size() are zero (.bss)
  std::vector<uint8_t> bytes;  // the file's bytes
};

struct ElfImage {
  std::string path;
  std::vector<ElfSegment> segments;
  std::map<std::string, uint32_t> symbols;  // every named symbol's value (a function's with its Thumb bit)
  uint32_t symbol(const std::string& name) const { return symbols.at(name); }
};

// The symbols the virtual board calls or reads (examples/firmware/target/psbsp_board.c
// and psbsp_cm4.ld); an ELF without one of them is refused.
extern const char* const kTargetRequiredSymbols[];
extern const size_t kTargetRequiredSymbolCount;

// Reads and checks `path` (ELF32, little-endian, EM_ARM, executable, segments inside
// the virtual MCU's flash and RAM, the required symbols). Throws ElfError.
ElfImage readTargetElf(const std::string& path);

}  // namespace packsim

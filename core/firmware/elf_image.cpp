#include "core/firmware/elf_image.hpp"

#include <elf.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/firmware/target_memory_map.hpp"

namespace packsim {

const char* const kTargetRequiredSymbols[] = {
    "psbsp_entry",          "psbsp_init",         "psbsp_task",          "psbsp_api",
    "__psbsp_bss_start",    "__psbsp_bss_end",    "__psbsp_noinit_start", "__psbsp_noinit_end",
    "__psbsp_free_start",   "__psbsp_stack_limit", "__psbsp_stack_top",
};
const size_t kTargetRequiredSymbolCount = sizeof kTargetRequiredSymbols / sizeof kTargetRequiredSymbols[0];

namespace {

const char* machineName(unsigned m) {
  switch (m) {
    case EM_386: return "x86";
    case EM_X86_64: return "x86-64";
    case EM_AARCH64: return "AArch64";
    case EM_RISCV: return "RISC-V";
    case EM_ARM: return "ARM";
    default: return "another machine";
  }
}

template <typename T>
T readAt(const std::vector<uint8_t>& f, size_t off, const std::string& path, const char* what) {
  if (off > f.size() || f.size() - off < sizeof(T))
    throw ElfError(path, what, "lies past the end of the file (" + std::to_string(f.size()) + " bytes): truncated ELF");
  T v;
  std::memcpy(&v, f.data() + off, sizeof v);
  return v;
}

bool inside(uint32_t a, uint32_t n, uint32_t base, uint32_t size) {
  return a >= base && uint64_t{a} + n <= uint64_t{base} + size;
}

}  // namespace

ElfImage readTargetElf(const std::string& path) {
  constexpr std::uintmax_t kMaxElfBytes = 64u << 20;  // 1 MiB of flash, the rest debug information
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw ElfError(path, "file", "cannot be read (" + ec.message() + ")");
  if (size > kMaxElfBytes) throw ElfError(path, "file", "larger than 64 MiB: not a firmware ELF for 1 MiB of flash");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ElfError(path, "file", "cannot be opened");
  const std::vector<uint8_t> f((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (f.size() < EI_NIDENT || std::memcmp(f.data(), ELFMAG, SELFMAG) != 0)
    throw ElfError(path, "e_ident", "not an ELF file (no \\x7fELF magic)");
  // e_machine sits at the same offset in ELF32 and ELF64 headers: the architecture first.
  if (f.size() < 20) throw ElfError(path, "ELF header", "truncated (" + std::to_string(f.size()) + " bytes)");
  const unsigned machine = f[18] | (unsigned{f[19]} << 8);
  if (machine != EM_ARM)
    throw ElfError(path, "e_machine", std::to_string(machine) + " (" + machineName(machine) +
                                          "); a cortex-m4 target needs 40 (ARM), built with arm-none-eabi-gcc");
  if (f[EI_CLASS] != ELFCLASS32)
    throw ElfError(path, "e_ident[EI_CLASS]", "a 64-bit ELF; a Cortex-M4 firmware is ELF32 (arm-none-eabi-gcc)");
  if (f[EI_DATA] != ELFDATA2LSB) throw ElfError(path, "e_ident[EI_DATA]", "big-endian; the Cortex-M4 is little-endian");
  const auto eh = readAt<Elf32_Ehdr>(f, 0, path, "ELF header");
  if (eh.e_type != ET_EXEC)
    throw ElfError(path, "e_type", std::to_string(eh.e_type) +
                                       "; expected 2 (an executable linked with psbsp_cm4.ld, not an object or library)");
  ElfImage img;
  img.path = path;
  for (unsigned i = 0; i < eh.e_phnum; ++i) {
    const auto ph = readAt<Elf32_Phdr>(f, eh.e_phoff + size_t{i} * eh.e_phentsize, path, "program header");
    if (ph.p_type != PT_LOAD || ph.p_memsz == 0) continue;
    const std::string field = "program header " + std::to_string(i);
    if (ph.p_filesz > ph.p_memsz || ph.p_offset > f.size() || f.size() - ph.p_offset < ph.p_filesz)
      throw ElfError(path, field, "file bytes past the end of the file or above p_memsz");
    const bool inFlash = inside(ph.p_vaddr, ph.p_memsz, target::kFlashBase, target::kFlashBytes);
    const bool inRam = inside(ph.p_vaddr, ph.p_memsz, target::kRamBase, target::kRamBytes);
    if (!inFlash && !inRam) {
      char where[160];
      std::snprintf(where, sizeof where,
                    "p_vaddr 0x%08x + %u bytes lies outside flash [0x%08x, +%u KiB) and RAM [0x%08x, +%u KiB)",
                    ph.p_vaddr, ph.p_memsz, target::kFlashBase, target::kFlashBytes / 1024, target::kRamBase,
                    target::kRamBytes / 1024);
      throw ElfError(path, field, where);
    }
    ElfSegment s;
    s.vaddr = ph.p_vaddr;
    s.memsz = ph.p_memsz;
    s.bytes.assign(f.begin() + ph.p_offset, f.begin() + ph.p_offset + ph.p_filesz);
    img.segments.push_back(std::move(s));
  }
  if (img.segments.empty()) throw ElfError(path, "program headers", "no loadable segment");
  // The symbol table (.symtab and its string table).
  for (unsigned i = 0; i < eh.e_shnum; ++i) {
    const auto sh = readAt<Elf32_Shdr>(f, eh.e_shoff + size_t{i} * eh.e_shentsize, path, "section header");
    if (sh.sh_type != SHT_SYMTAB) continue;
    const auto strs = readAt<Elf32_Shdr>(f, eh.e_shoff + size_t{sh.sh_link} * eh.e_shentsize, path, "section header");
    for (uint32_t k = 0; k + sizeof(Elf32_Sym) <= sh.sh_size; k += sizeof(Elf32_Sym)) {
      const auto sym = readAt<Elf32_Sym>(f, sh.sh_offset + k, path, "symbol");
      if (sym.st_name == 0 || strs.sh_offset + sym.st_name >= f.size()) continue;
      const char* name = reinterpret_cast<const char*>(f.data() + strs.sh_offset + sym.st_name);
      const size_t maxLen = f.size() - (strs.sh_offset + sym.st_name);
      img.symbols.emplace(std::string(name, strnlen(name, maxLen)), sym.st_value);
    }
  }
  for (size_t i = 0; i < kTargetRequiredSymbolCount; ++i)
    if (!img.symbols.count(kTargetRequiredSymbols[i]))
      throw ElfError(path, std::string("symbol ") + kTargetRequiredSymbols[i],
                     "missing (stripped, or not linked with examples/firmware/target's psbsp_board.c and psbsp_cm4.ld)");
  if (!img.symbols.count("psfw_firmware_entry"))
    throw ElfError(path, "symbol psfw_firmware_entry", "missing: the firmware's entry (packsim_fw.h) is not linked in");
  return img;
}

}  // namespace packsim

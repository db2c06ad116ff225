#include "core/firmware/config_schema.hpp"

#include <bms/packsim_fw.h>
#include <dlfcn.h>

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <set>

#include "core/firmware/elf_image.hpp"
#include "core/firmware/fault_guard.hpp"

namespace packsim {

namespace {

constexpr size_t kMaxBlobBytes = 65536;  // as bms.firmware.config_file
// Longest texts a field may carry, the terminating NUL included.
constexpr size_t kNameChars = 64, kUnitChars = 32, kDocChars = 200;
constexpr uint32_t kMaxCount = 4096;

// One field as the firmware wrote it, before the checks.
struct RawField {
  double min, max, def;
  uint32_t type, count;
  char name[kNameChars], unit[kUnitChars], doc[kDocChars];
  bool nameNull, nameLong, unitLong, docLong;
};

// A NUL-terminated text of at most n - 1 characters into out (false: longer).
template <typename ReadByte>
bool copyText(ReadByte byteAt, char* out, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    out[i] = byteAt(i);
    if (out[i] == '\0') return true;
  }
  out[n - 1] = '\0';
  return false;
}

std::string numberText(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

bool validName(const char* s) {
  if (!*s || std::isdigit(static_cast<unsigned char>(*s))) return false;
  for (; *s; ++s)
    if (!std::isalnum(static_cast<unsigned char>(*s)) && *s != '_') return false;
  return true;
}

// The rules of packsim_fw.h, field by field; the error names the field.
ConfigSchema checked(uint32_t version, uint32_t count, const std::vector<RawField>& raw) {
  if (version != PSFW_CONFIG_SCHEMA_VERSION)
    throw ConfigSchemaError("version " + std::to_string(version) + ", this packsim reads version " +
                            std::to_string(PSFW_CONFIG_SCHEMA_VERSION));
  if (count > PSFW_CONFIG_MAX_FIELDS)
    throw ConfigSchemaError(std::to_string(count) + " fields, more than " + std::to_string(PSFW_CONFIG_MAX_FIELDS));
  ConfigSchema s;
  std::set<std::string> names;
  size_t bytes = 0;
  for (size_t i = 0; i < raw.size(); ++i) {
    const RawField& r = raw[i];
    std::string at = "field " + std::to_string(i);
    if (r.nameNull) throw ConfigSchemaError(at + ": no name");
    if (r.nameLong) throw ConfigSchemaError(at + ": a name longer than " + std::to_string(kNameChars - 1) + " characters");
    at += " '" + std::string(r.name) + "'";
    if (!validName(r.name)) throw ConfigSchemaError(at + ": a name of letters, digits and '_' (not starting with a digit) expected");
    if (!names.insert(r.name).second) throw ConfigSchemaError(at + ": the name twice");
    if (r.unitLong || r.docLong) throw ConfigSchemaError(at + ": a unit or doc line too long");
    if (r.type != PSFW_CONFIG_INT32 && r.type != PSFW_CONFIG_FLOAT32)
      throw ConfigSchemaError(at + ": type " + std::to_string(r.type) + " (PSFW_CONFIG_INT32 or PSFW_CONFIG_FLOAT32 expected)");
    if (r.count < 1 || r.count > kMaxCount)
      throw ConfigSchemaError(at + ": count " + std::to_string(r.count) + " (1 to " + std::to_string(kMaxCount) + " expected)");
    ConfigField f{r.name, r.unit, r.doc, r.type == PSFW_CONFIG_FLOAT32, r.count, r.min, r.max, r.def};
    const double lim = f.real ? static_cast<double>(FLT_MAX) : static_cast<double>(std::numeric_limits<int32_t>::max());
    const double low = f.real ? -lim : static_cast<double>(std::numeric_limits<int32_t>::min());
    for (const auto& [what, v] : {std::pair<const char*, double>{"min", f.min}, {"max", f.max}, {"default", f.def}}) {
      if (!std::isfinite(v) || v < low || v > lim)
        throw ConfigSchemaError(at + ": " + what + " " + numberText(v) + " is not a" + (f.real ? " float" : "n int32"));
      if (!f.real && v != std::floor(v)) throw ConfigSchemaError(at + ": " + what + " " + numberText(v) + " is not a whole number");
    }
    if (f.min > f.max) throw ConfigSchemaError(at + ": min " + numberText(f.min) + " > max " + numberText(f.max));
    if (f.def < f.min || f.def > f.max)
      throw ConfigSchemaError(at + ": default " + numberText(f.def) + " outside [" + numberText(f.min) + ", " + numberText(f.max) + "]");
    bytes += 4u * f.count;
    if (bytes > kMaxBlobBytes) throw ConfigSchemaError("a blob larger than " + std::to_string(kMaxBlobBytes) + " bytes");
    s.fields.push_back(std::move(f));
  }
  return s;
}

// ---- host: the library's table, copied under the fault guard ----

struct HostRead {
  const psfw_config_schema* schema;
  uint32_t version = 0, count = 0;
  bool fieldsNull = false;
  std::vector<RawField>* out;
};

void copyHostSchema(void* p) {
  HostRead& h = *static_cast<HostRead*>(p);
  h.version = h.schema->version;
  h.count = h.schema->field_count;
  h.fieldsNull = h.count > 0 && !h.schema->fields;
  if (h.count > PSFW_CONFIG_MAX_FIELDS || h.fieldsNull) return;
  for (uint32_t i = 0; i < h.count; ++i) {
    const psfw_config_field& f = h.schema->fields[i];
    RawField& r = (*h.out)[i];
    r.min = f.min;
    r.max = f.max;
    r.def = f.def;
    r.type = f.type;
    r.count = f.count;
    r.nameNull = f.name == nullptr;
    r.nameLong = !r.nameNull && !copyText([&](size_t k) { return f.name[k]; }, r.name, kNameChars);
    r.unitLong = f.unit && !copyText([&](size_t k) { return f.unit[k]; }, r.unit, kUnitChars);
    r.docLong = f.doc && !copyText([&](size_t k) { return f.doc[k]; }, r.doc, kDocChars);
  }
}

// ---- target: the table's bytes in the ELF's segments (32-bit layout) ----

// The ARM EABI layout of packsim_fw.h's structs (doubles 8-aligned, pointers 4 bytes):
// psfw_config_schema {version @0, field_count @4, fields @8}, psfw_config_field below.
constexpr uint32_t kArmFieldBytes = 48;
enum : uint32_t { kMin = 0, kMax = 8, kDef = 16, kName = 24, kUnit = 28, kDoc = 32, kType = 36, kCount = 40 };

class ElfMemory {
 public:
  explicit ElfMemory(const ElfImage& e) : elf_(e) {}
  // n bytes at address a of the image (its file bytes; .bss is not a schema's place).
  void read(uint32_t a, uint32_t n, void* out, const std::string& what) const {
    for (const ElfSegment& s : elf_.segments)
      if (a >= s.vaddr && uint64_t{a} + n <= uint64_t{s.vaddr} + s.bytes.size()) {
        std::memcpy(out, s.bytes.data() + (a - s.vaddr), n);
        return;
      }
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%08x", a);
    throw ConfigSchemaError(what + " at " + hex + " is not in the ELF's loaded bytes");
  }
  uint32_t u32(uint32_t a, const std::string& what) const {
    uint8_t b[4];
    read(a, 4, b, what);
    return uint32_t{b[0]} | uint32_t{b[1]} << 8 | uint32_t{b[2]} << 16 | uint32_t{b[3]} << 24;
  }
  double f64(uint32_t a, const std::string& what) const {
    const uint64_t bits = u32(a, what) | uint64_t{u32(a + 4, what)} << 32;
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  char byteAt(uint32_t a, const std::string& what) const {
    char c;
    read(a, 1, &c, what);
    return c;
  }

 private:
  const ElfImage& elf_;
};

}  // namespace

size_t ConfigSchema::blobBytes() const {
  size_t n = 0;
  for (const ConfigField& f : fields) n += 4u * f.count;
  return n;
}

std::optional<ConfigSchema> readLibraryConfigSchema(const std::string& path) {
  void* lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib) return std::nullopt;
  const auto* schema = static_cast<const psfw_config_schema*>(dlsym(lib, PSFW_CONFIG_SCHEMA_SYMBOL));
  if (!schema) {
    dlclose(lib);
    return std::nullopt;
  }
  std::vector<RawField> raw(PSFW_CONFIG_MAX_FIELDS);
  HostRead h{schema, 0, 0, false, &raw};
  GuardResult g;
  {
    FaultGuard guard(1.0);
    FaultGuard::Scope scope;
    g = guard.run(copyHostSchema, &h);
  }
  dlclose(lib);
  if (g.outcome != GuardOutcome::Ok)
    throw ConfigSchemaError("reading it crashed (signal " + std::to_string(g.signal) + "): a pointer in it is wrong");
  if (h.fieldsNull) throw ConfigSchemaError(std::to_string(h.count) + " fields but a null field table");
  raw.resize(std::min<size_t>(h.count, PSFW_CONFIG_MAX_FIELDS));
  return checked(h.version, h.count, raw);
}

std::optional<ConfigSchema> readElfConfigSchema(const ElfImage& elf) {
  // An ELF without the schema may still name the symbol, undefined (value 0): the
  // build's -u psfw_firmware_config_schema (build-cm4.sh) leaves it so. The table lives in
  // flash (0x08000000 on), never at 0.
  const auto sym = elf.symbols.find(PSFW_CONFIG_SCHEMA_SYMBOL);
  if (sym == elf.symbols.end() || sym->second == 0) return std::nullopt;
  const ElfMemory mem(elf);
  const uint32_t at = sym->second;
  const uint32_t version = mem.u32(at, "the schema"), count = mem.u32(at + 4, "the schema");
  const uint32_t fields = mem.u32(at + 8, "the schema");
  if (count > PSFW_CONFIG_MAX_FIELDS) return checked(version, count, {});
  std::vector<RawField> raw(count);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t f = fields + i * kArmFieldBytes;
    const std::string what = "field " + std::to_string(i);
    RawField& r = raw[i];
    r.min = mem.f64(f + kMin, what);
    r.max = mem.f64(f + kMax, what);
    r.def = mem.f64(f + kDef, what);
    r.type = mem.u32(f + kType, what);
    r.count = mem.u32(f + kCount, what);
    const uint32_t name = mem.u32(f + kName, what), unit = mem.u32(f + kUnit, what), doc = mem.u32(f + kDoc, what);
    r.nameNull = name == 0;
    auto text = [&](uint32_t a, char* out, size_t n, const char* which) {
      return copyText([&](size_t k) { return mem.byteAt(a + static_cast<uint32_t>(k), what + "'s " + which); }, out, n);
    };
    r.nameLong = !r.nameNull && !text(name, r.name, kNameChars, "name");
    r.unitLong = unit != 0 && !text(unit, r.unit, kUnitChars, "unit");
    r.docLong = doc != 0 && !text(doc, r.doc, kDocChars, "doc");
  }
  return checked(version, count, raw);
}

}  // namespace packsim

#include "bms_settings.hpp"

namespace bms {

void settingDefaults(Config& c) {
#define BMS_DEFAULT(field, value)                              \
  {                                                            \
    constexpr double v_ = (value);                             \
    constexpr long r_ = roundedSetting(v_);                    \
    constexpr float f_ = static_cast<float>(v_);               \
    defaultSetting(c.field, r_, f_);                           \
  }
#define BMS_NUMBER(key, field, unit, fwUnit, mul, div, def, lo, hi, loOpen, doc) BMS_DEFAULT(field, (def) * (mul) / (div))
#define BMS_INTEGER(key, field, unit, def, lo, hi, doc) BMS_DEFAULT(field, (def))
#define BMS_FLAG(key, field, def, doc) c.field = (def);
#define BMS_ENABLE(key, field, doc) c.field = false;
#define BMS_CHOICE(key, field, def, names, doc) c.field = (def);
#include "bms_settings.def"
#undef BMS_DEFAULT
#undef BMS_NUMBER
#undef BMS_INTEGER
#undef BMS_FLAG
#undef BMS_ENABLE
#undef BMS_CHOICE
}

void copySettings(Config& to, const Config& from) {
#define BMS_ROW(field) to.field = from.field;
#define BMS_NUMBER(key, field, unit, fwUnit, mul, div, def, lo, hi, loOpen, doc) BMS_ROW(field)
#define BMS_INTEGER(key, field, unit, def, lo, hi, doc) BMS_ROW(field)
#define BMS_FLAG(key, field, def, doc) BMS_ROW(field)
#define BMS_ENABLE(key, field, doc) BMS_ROW(field)
#define BMS_CHOICE(key, field, def, names, doc) BMS_ROW(field)
#include "bms_settings.def"
#undef BMS_ROW
#undef BMS_NUMBER
#undef BMS_INTEGER
#undef BMS_FLAG
#undef BMS_ENABLE
#undef BMS_CHOICE
}

}  // namespace bms

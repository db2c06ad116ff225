// The BMS core's scalar settings as one table (bms_settings.def): their defaults and
// their copy from a configured image. The simulator's loader converts a key's value
// with setSetting (lround: the host's libm); the firmware's defaults are the same
// conversion of the row's default, folded at compile time (defaultSetting: no libm, no
// double arithmetic on the target). tests/core/bms_setting_table_test.cpp checks that
// both give the same field for every row.
#pragma once
#include <math.h>
#include <stdint.h>

#include "bms_config.hpp"

namespace bms {

// A value in firmware units (key value * MUL / DIV) into a field of its type.
inline void setSetting(bool& f, double v) { f = v != 0.0; }
inline void setSetting(float& f, double v) { f = static_cast<float>(v); }
inline void setSetting(uint8_t& f, double v) { f = static_cast<uint8_t>(lround(v)); }
inline void setSetting(uint16_t& f, double v) { f = static_cast<uint16_t>(lround(v)); }
inline void setSetting(int16_t& f, double v) { f = static_cast<int16_t>(lround(v)); }
inline void setSetting(uint32_t& f, double v) { f = static_cast<uint32_t>(lround(v)); }
inline void setSetting(int32_t& f, double v) { f = static_cast<int32_t>(lround(v)); }
template <class Enum>
inline void setSetting(Enum& f, double index) { f = static_cast<Enum>(static_cast<int>(index)); }

// Half away from zero, as lround (for the constant defaults; folded by the compiler).
constexpr long roundedSetting(double v) { return static_cast<long>(v >= 0.0 ? v + 0.5 : v - 0.5); }
// A default: its value rounded (integer fields) and as a float (float fields), both constants.
inline void defaultSetting(bool& f, long r, float) { f = r != 0; }
inline void defaultSetting(float& f, long, float v) { f = v; }
inline void defaultSetting(uint8_t& f, long r, float) { f = static_cast<uint8_t>(r); }
inline void defaultSetting(uint16_t& f, long r, float) { f = static_cast<uint16_t>(r); }
inline void defaultSetting(int16_t& f, long r, float) { f = static_cast<int16_t>(r); }
inline void defaultSetting(uint32_t& f, long r, float) { f = static_cast<uint32_t>(r); }
inline void defaultSetting(int32_t& f, long r, float) { f = static_cast<int32_t>(r); }

// Every row's default (bms_settings.def) into `c`.
void settingDefaults(Config& c);
// Every row's field from `from` into `to` (the rest of `to` unchanged).
void copySettings(Config& to, const Config& from);

}  // namespace bms

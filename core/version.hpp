#pragma once
namespace packsim {
inline constexpr const char* kVersion = "0.1.0";
}

// The unit a CSV column's name ends in -- "t_ms", "Time (ms)", "I [mA]", "power_kW" -- as
// its factor to seconds, amperes or watts: a log whose time is in milliseconds read as
// seconds is a profile a thousand times too long, and nothing in its numbers says so.
#pragma once
#include <string>

namespace packsim {

struct NamedUnit {
  std::string unit;     // as written in the name ("ms"); empty: none recognised
  double factor = 0.0;  // to s, A or W; 0: none recognised
};

NamedUnit timeUnitOfName(const std::string& column);
// A current column's unit (A, mA, kA) or, with power, a power column's (W, mW, kW).
NamedUnit valueUnitOfName(const std::string& column, bool power);

}  // namespace packsim

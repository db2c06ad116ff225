// The relay contact as the run's relay_contact events record it -- what the contact did,
// never what was commanded: for the summary's trip and FAULT-line lines and `check`.
#pragma once
#include <string>

#include "core/sim/result.hpp"

namespace packsim {

// Whether the contact was closed just before time t (open until an event says otherwise).
bool contactClosedBefore(const RunResult& r, double t);
// What the contact did from time t on: "the relay contact opened at 12.34 s", "... had
// opened at ...", "... stayed closed to the end", with any closing again after.
std::string contactFrom(const RunResult& r, double t);
// Whether the contact was open at some time at or after t (it opened, or was open then).
bool contactOpenFrom(const RunResult& r, double t);

}  // namespace packsim

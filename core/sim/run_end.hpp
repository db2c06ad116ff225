// Why a run ended: the `run` event's detail is "end: <reason>" (RunTracker::finish); the
// summary's duration line names any reason but the scheduled one.
#pragma once

namespace packsim {

inline constexpr char kRunEndEventPrefix[] = "end: ";
inline constexpr char kRunEndScheduled[] = "the scenario's end time";

}  // namespace packsim

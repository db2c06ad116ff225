// Which BMS faults a scripted injection can cause (packsim check attributes each
// detection to the injection that caused it, not to whatever fault comes next).
#pragma once
#include <string>
#include <vector>

#include "core/scenario/faults_config.hpp"
#include "core/sim/result.hpp"

namespace packsim {

// The protection rows (bms::faultName) an injection of this kind can raise, directly or
// through what it does to the pack; empty for operator inputs (reset_request, key_off).
const std::vector<std::string>& faultsCausedBy(FaultKind kind);
// The kind named by a fault_injected event's detail (its first word); false if none.
bool faultKindOfDetail(const std::string& detail, FaultKind& kind);

// One scripted injection as the events record it: from its fault_injected event to its
// fault_removed event (paired in order among injections of the same detail), or to the
// end of the run.
struct InjectionSpan {
  const Event* injected = nullptr;
  double start_s = 0.0;
  double end_s = 0.0;  // +inf: never removed
  bool known = false;  // its kind was recognised (faultKindOfDetail)
  FaultKind kind = FaultKind::Overcurrent;
};
std::vector<InjectionSpan> injectionSpans(const std::vector<Event>& events);

// The injection a BMS fault `name` raised at t belongs to rather than `own`: one that can
// cause it too and started after `own` had been removed, by t. Null when none: then `own`
// may have caused it. (Injections that overlap cannot be told apart and both keep it.)
const InjectionSpan* laterCause(const std::vector<InjectionSpan>& spans, const InjectionSpan& own,
                                const std::string& name, double t_s);

}  // namespace packsim

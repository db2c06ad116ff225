// The run summary as the few lines a battery engineer reads first.
#pragma once
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/result.hpp"

namespace packsim {

class LineWriter;

// The summary is a table of lines: one row per line (or lines under one label), in the
// order printed; formatSummary writes each row.
struct SummaryLine {
  const char* label;   // its first 16 columns (a row may give some lines a label of their own)
  const char* fields;  // the /summary figures it prints: summaryFields() names, space-separated
  void (*write)(LineWriter& w, const Scenario& s, const RunResult& r);  // none, one or more lines
};
const std::vector<SummaryLine>& summaryLines();

std::string formatSummary(const Scenario& s, const RunResult& r);
// "cell N" (1-based over every cell), with its series group in a pack of parallel cells:
// "cell 74 (group 19)" in a 24s4p pack.
std::string cellName(int cell, int parallel);
// The truth when the BMS switched the charger off (ChargeSummary): "the highest cell,
// cell 5 (group 3), at 4.149 V under 3.00 A of charge, mean SOC 0.838 (truth)" -- its
// `charger` event and balance-time's note.
std::string chargeOffText(const ChargeSummary& c, int parallel);
// "never closed in the run's 60.00 s: the load asked for up to 5.90 A discharge and drew
// 0.000 Ah; the BMS's last state: standby" when the relay never closed (Summary::relay_closed:
// no relay_contact event said it did) while the load or charger asked for current; ""
// otherwise. The summary's
// `relay` line and a `check` warning: a run with no trip that delivered nothing.
std::string relayNeverClosed(const Scenario& s, const RunResult& r);
// A duration as h:mm:ss, rounded to the second.
std::string clockText(double s);

}  // namespace packsim

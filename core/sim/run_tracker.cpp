#include "core/sim/run_tracker.hpp"

#include "core/scenario/bms_setting_table.hpp"
#include "core/sim/result_channels.hpp"
#include "core/sim/run_end.hpp"
#include "core/sim/stranded_energy.hpp"
#include "core/sim/summary_text.hpp"

#include <bms/bms_balance.hpp>
#include <bms/bms_core.hpp>
#include <bms/bms_names.hpp>
#include <bms/bms_soc.hpp>
#include <bms/bms_telemetry.hpp>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace packsim {

namespace {

// The switching hardware's own events: one row per flag of HardwareStatus, the event it
// raises when the flag sets and (falling: non-null) when it clears, in this order
// within a tick. (A new row's flag must be one sameEventFlags compares: RunTracker's
// constructor checks.)
struct HardwareEdge {
  bool HardwareStatus::*flag;
  const char* kind;
  const char* rising;
  const char* falling;
};
constexpr HardwareEdge kHardwareEdges[] = {
    {&HardwareStatus::relay_closed, "relay_contact", "closed", "opened"},
    {&HardwareStatus::precharge_closed, "precharge_contact", "closed", "opened"},
    {&HardwareStatus::fuse_blown, "fuse", "blown", nullptr},
    {&HardwareStatus::fault_line, "monitor_fault_line", "asserted", "released"},
    {&HardwareStatus::charger_cv, "charger", "constant voltage", nullptr},
    {&HardwareStatus::charger_done, "charger", "done (taper end current)", nullptr},
};

// Whether every flag an event of hardwareChanged reads (kHardwareEdges, the active
// balancer's two) is the same in a and b, compared as HardwareStatus's two runs of
// bools (the first also holds the FET gates, which no event reads: a change of one only
// takes the row-by-row look): the usual tick, one compare each instead of that look.
bool sameEventFlags(const HardwareStatus& a, const HardwareStatus& b) {
  using H = HardwareStatus;
  static_assert(offsetof(H, fault_line) - offsetof(H, relay_closed) == 5 &&
                    offsetof(H, precharge_closed) == offsetof(H, relay_closed) + 1 &&
                    offsetof(H, fuse_blown) == offsetof(H, relay_closed) + 2,
                "HardwareStatus: relay_closed .. fault_line are 6 bools in a row");
  static_assert(offsetof(H, charger_done) == offsetof(H, charger_cv) + 1 &&
                    offsetof(H, active_safe_state) == offsetof(H, charger_cv) + 2 &&
                    offsetof(H, active_isolated) == offsetof(H, charger_cv) + 3,
                "HardwareStatus: charger_cv .. active_isolated are 4 bools in a row");
  return std::memcmp(&a.relay_closed, &b.relay_closed, 6) == 0 && std::memcmp(&a.charger_cv, &b.charger_cv, 4) == 0;
}

// sameEventFlags covers every flag an event reads: each one set alone differs from none.
bool everyEventFlagCompared() {
  bool HardwareStatus::*const active[] = {&HardwareStatus::active_safe_state, &HardwareStatus::active_isolated};
  std::vector<bool HardwareStatus::*> flags(active, active + 2);
  for (const HardwareEdge& e : kHardwareEdges) flags.push_back(e.flag);
  for (bool HardwareStatus::*f : flags) {
    HardwareStatus none, one;
    one.*f = true;
    if (sameEventFlags(none, one)) return false;
  }
  return true;
}

// The firmware's own events: one row per field of bms::Outputs that raises events, the
// field read as a number. A value row raises `kind` when the number changes (and, with
// on_first, at the first tick, the number before it then being 0); a mask row raises
// `kind` for each bit that sets and `falling` (non-null) for each that clears. Rows are
// taken in table order, except that consecutive mask rows go bit by bit together, so a
// fault's fault_active and fault_latched stand side by side. The detail is the value's
// (or bit's) name, after "before -> " with shows_before, followed by `more` when the
// row has one (not for a falling bit); a value at or past `names` (0: no bound) is no
// event. Rows marked `report` state what the hardware did: they follow the hardware's
// own events (kHardwareEdges) in a tick; the others are the firmware's decisions and
// precede them. The table is packsim's core's: its fields but the relay pin are what the
// debug probe finds in the core's RAM, which a user's firmware never writes (they stay
// at zero: a `bms_state init` or `balancing disabled` at t = 0 named a state it was never
// in), and its relay events are at the tick of the control step that decided; a user's
// firmware's `relay` events come from its pin writes, at their instants (pinsWritten).
struct OutputEdge {
  enum Needs : uint8_t { kAlways, kHardware, kBalancing };
  const char* kind;
  const char* falling;  // mask rows: the kind when a bit clears (nullptr: none)
  uint64_t (*read)(const bms::Outputs&);
  bool mask;            // one event per bit (bits: `names` of them)
  Needs needs;          // a run with a hardware simulation / balancing hardware only
  bool report;
  bool on_first;
  bool shows_before;
  unsigned names;
  std::string (*name)(uint64_t value);  // a value's or a bit's name
  std::string (*more)(const bms::Config& cfg, const bms::Outputs& out, uint64_t value) = nullptr;
};

std::string stateText(uint64_t v) { return bms::stateName(static_cast<bms::State>(v)); }
std::string faultText(uint64_t bit) { return bms::faultName(static_cast<bms::FaultId>(bit)); }
std::string relayText(uint64_t v) { return v ? "close" : "open"; }
std::string prechargeText(uint64_t v) { return bms::prechargePhaseName(static_cast<bms::PrechargePhase>(v)); }
std::string deviceText(uint64_t bit) { return "device " + std::to_string(bit + 1); }
std::string balancingText(uint64_t v) { return bms::balanceStatusName(static_cast<bms::BalanceStatus>(v)); }

// fault_active: the protection's threshold, delay and reading, and how its action applies.
std::string faultMore(const bms::Config& cfg, const bms::Outputs& out, uint64_t bit) {
  const auto id = static_cast<bms::FaultId>(bit);
  const bms::ProtectionRule& rule = cfg.rules[static_cast<int>(id)];
  std::string d = ": " + protectionDetail(id, rule.threshold, rule.delay_ms, out.telemetry);
  if (rule.severity == bms::Severity::Fatal && rule.action == bms::FaultAction::Monitor) d += " (monitor only)";
  if (rule.severity == bms::Severity::Fatal && rule.action == bms::FaultAction::MonitorWhileDriving)
    d += out.state == bms::State::Normal ? " (monitored while driving)" : " (isolates off track)";
  return d;
}
std::string prechargeMore(const bms::Config&, const bms::Outputs& out, uint64_t) {
  return " (attempt " + std::to_string(out.telemetry.prechargeAttempts) + ")";
}

using O = bms::Outputs;
// clang-format off
constexpr OutputEdge kOutputEdges[] = {
  // kind           falling          read                                                       mask   needs                   report on_first before names                 name
  {"bms_state",     nullptr,         [](const O& o) -> uint64_t { return static_cast<uint64_t>(o.state); },   false, OutputEdge::kAlways,    false, true,  true,  0,                     stateText},
  {"fault_active",  "fault_cleared", [](const O& o) -> uint64_t { return o.faultActive; },                    true,  OutputEdge::kAlways,    false, false, false, bms::kFaultCount,      faultText, faultMore},
  {"fault_latched", nullptr,         [](const O& o) -> uint64_t { return o.faultLatched; },                   true,  OutputEdge::kAlways,    false, false, false, bms::kFaultCount,      faultText},
  {"relay",         nullptr,         [](const O& o) -> uint64_t { return o.relayClose; },                     false, OutputEdge::kAlways,    false, false, false, 0,                     relayText},
  {"precharge",     nullptr,         [](const O& o) -> uint64_t { return o.telemetry.prechargePhase; },       false, OutputEdge::kHardware,  true,  false, false, bms::kPrechargePhaseCount, prechargeText, prechargeMore},
  {"comm_lost",     nullptr,         [](const O& o) -> uint64_t { return o.telemetry.devicesLost; },          true,  OutputEdge::kHardware,  true,  false, false, 64,                    deviceText},
  {"balancing",     nullptr,         [](const O& o) -> uint64_t { return o.balanceStatus; },                  false, OutputEdge::kBalancing, true,  true,  false, bms::kBalanceStatusCount, balancingText},
};
// clang-format on
constexpr size_t kOutputEdgeCount = sizeof kOutputEdges / sizeof kOutputEdges[0];

// Whether a row applies to this run (its needs met: a hardware simulation, balancing hardware).
bool rowApplies(const OutputEdge& e, bool hardware, bool balancing) {
  return !((e.needs == OutputEdge::kHardware && !hardware) || (e.needs == OutputEdge::kBalancing && !balancing));
}

// Whether some row that applies reads other than at the last tick. If none does (and it
// is not the first tick), outputEvents has no event to raise and nothing to note: the
// usual tick, so it is skipped. Row by row in table order as a fold over the indices:
// each row's needs and reader are constants (kOutputEdges is constexpr), so the readers
// are inlined instead of called through their pointers (once per tick, every tick).
template <size_t... I>
bool anyRowChanged(const bms::Outputs& out, const uint64_t* last, bool hardware, bool balancing,
                   std::index_sequence<I...>) {
  return ((rowApplies(kOutputEdges[I], hardware, balancing) && kOutputEdges[I].read(out) != last[I]) || ...);
}
bool anyOutputChanged(const bms::Outputs& out, const uint64_t* last, bool hardware, bool balancing) {
  return anyRowChanged(out, last, hardware, balancing, std::make_index_sequence<kOutputEdgeCount>{});
}

// The index of the first of the values equal to v (v is one of them).
int firstCellAt(const double* values, double v) {
  int c = 0;
  while (!(values[c] == v)) ++c;
  return c;
}

}  // namespace

RunTracker::RunTracker(const Scenario& s, const Plant& plant, const bms::Config& cfg)
    : s_(s), plant_(plant), cfg_(cfg), core_(!s.bms.firmware.library), limits_(s, plant.pack().cellCount(), plant.pack().parallel),
      modelRange_(s.pack.cell), falseFaults_(s, plant.pack().parallel),
      limitSink_([this](double te, const std::string& d) { event(te, "limit_unseen", d); }),
      falseFaultSink_([this](double te, const std::string& d) { event(te, "false_fault", d); }) {
  Recording& rec = r_.rec;
  rec.cells = plant.pack().cellCount();
  rec.groups = plant.pack().series;
  rec.thermistors = s.hardware.thermistors.count();
  rec.has_balancing = s.hardware.balancing.present;
  rec.has_active_balancer = s.hardware.active_balancer.present;
  rec.has_charger = s.charger.present;
  r_.summary.charge.present = s.charger.present;
  rec.has_board = plant.boardNode() >= 0;
  r_.summary.scenario = s.name;
  r_.summary.soc_estimator = settingChoice("soc.estimator", s.bms.image);
  for (const auto& cell : plant.pack().cells) r_.summary.capacity_true_Ah += cell.capacity_Ah;
  r_.summary.capacity_true_Ah /= plant.pack().series;
  for (const auto& cell : plant.pack().cells) {
    cellMin_V_.push_back(cell.v_min_V);
    if (cell.v_min_V > highestMin_V_) highestMin_V_ = cell.v_min_V;  // (a NaN limit, which no voltage reaches, left out)
  }
  const std::vector<double> state(static_cast<size_t>(plant.stateSize()));  // where cellStates points, as an index
  cellTemp_C_.assign(static_cast<size_t>(plant.pack().cellCount()), 0.0);  // filled by each tick
  for (int c = 0; c < plant.pack().cellCount(); ++c) {
    cellTempIndex_.push_back(static_cast<size_t>(plant.tempIndex(c)));
    cellSocIndex_.push_back(static_cast<size_t>(&plant.cellStates(state.data(), c)[CellLayout::soc] - state.data()));
  }
  static const bool flagsCovered = everyEventFlagCompared();  // once: a table row outside the compared bools
  if (!flagsCovered) throw std::logic_error("RunTracker: sameEventFlags misses a flag of kHardwareEdges");
  r_.summary.min_cell_V = INFINITY;
  r_.summary.max_temp_C = -INFINITY;
  for (int c = 0; c < plant.pack().cellCount(); ++c)
    r_.summary.energy_start_Wh += cellEnergy_Wh(plant.pack().cells[static_cast<size_t>(c)], plant.initialSoc()[static_cast<size_t>(c)]);
}

void RunTracker::noteLimit(double t, const double* x, int cell, bool byTrip) {
  Summary& sm = r_.summary;
  sm.limit_reached = true;
  sm.limit_by_bms_trip = byTrip;
  sm.limit_time_s = t;
  sm.limit_cell = cell + 1;
  limitSoc_.clear();
  for (int c = 0; c < plant_.pack().cellCount(); ++c) limitSoc_.push_back(plant_.cellStates(x, c)[CellLayout::soc]);
}

// A cell driven past empty or full is outside every curve's meaning: one event per
// cell and direction, the first time it happens (summary_text lists them).
void RunTracker::noteSocRange(double t, const double* x, int cell) {
  const double soc = plant_.cellStates(x, cell)[CellLayout::soc];
  const size_t ci = static_cast<size_t>(cell);
  if (socOut_.empty()) socOut_.assign(static_cast<size_t>(plant_.pack().cellCount()), 0);
  const uint8_t bit = soc < 0.0 ? 1 : soc > 1.0 ? 2 : 0;
  if (bit == 0 || (socOut_[ci] & bit)) return;
  socOut_[ci] |= bit;
  char buf[96];
  std::snprintf(buf, sizeof buf, " %s (SOC %.4f, capacity %.3f Ah)", bit == 1 ? "below SOC 0" : "above SOC 1", soc,
                plant_.pack().cells[ci].capacity_Ah);
  event(t, "soc_out_of_range", cellName(cell + 1, plant_.pack().parallel) + buf);
}

void RunTracker::setVehicle(const VehicleSample* v) {
  vehicle_ = v;
  r_.rec.has_vehicle = v != nullptr;
}

void RunTracker::setHardware(const HardwareSim* hw) {
  hw_ = hw;
  r_.rec.has_hardware = hw != nullptr;
  r_.rec.devices = hw ? hw->monitorDevices() : 0;
  misuseLogs_.clear();
  for (size_t b = 0; hw && b < hw->boards().size(); ++b)
    misuseLogs_.push_back(&hw->registerMisuse(static_cast<int>(b)).entries());
  misuseSeen_.resize(misuseLogs_.size(), 0);
}

void RunTracker::event(double t, const std::string& kind, const std::string& detail) {
  r_.events.push_back({t, kind, detail});
}

// A write a monitor IC ignored (read-only or reserved register, bad CRC/PEC, protected
// write): one register_misuse event per distinct (device, register, reason) at its
// first occurrence; finish() fills in how often it happened.
void RunTracker::noteMisuse() {
  for (size_t b = 0; b < misuseLogs_.size(); ++b) {
    const std::vector<RegisterMisuse>& log = *misuseLogs_[b];
    for (; misuseSeen_[b] < log.size(); ++misuseSeen_[b]) {
      misuseEvents_.push_back({static_cast<int>(b), misuseSeen_[b], r_.events.size()});
      event(log[misuseSeen_[b]].first_s, "register_misuse", misuseDetail(static_cast<int>(b), log[misuseSeen_[b]]));
    }
  }
}

std::string RunTracker::misuseDetail(int board, const RegisterMisuse& m) const {
  const MonitorBoard& b = hw_->boards()[static_cast<size_t>(board)];
  std::string who = s_.hardware.afe.model + (m.device < 0 ? " every device" : " device " + std::to_string(b.firstDevice + m.device + 1));
  if (hw_->boards().size() > 1) who += " (board " + std::to_string(board + 1) + ")";
  char times[96];
  if (m.count > 1) std::snprintf(times, sizeof times, "; %ld times, the last at %.4f s", m.count, m.last_s);
  else std::snprintf(times, sizeof times, "; once");
  return who + ": " + m.what + ": " + m.why + times;
}

namespace {

// kOutputEdges in runs [begin, end): a row alone, or consecutive mask rows that go bit
// by bit together (same bit count, side, needs). Fixed by the table: found once.
struct EdgeRun {
  size_t begin, end;
};
const std::vector<EdgeRun>& edgeRuns() {
  static const std::vector<EdgeRun> runs = [] {
    std::vector<EdgeRun> v;
    for (size_t i = 0, end; i < kOutputEdgeCount; i = end) {
      const OutputEdge& e = kOutputEdges[i];
      end = i + 1;
      while (e.mask && end < kOutputEdgeCount && kOutputEdges[end].mask && kOutputEdges[end].names == e.names &&
             kOutputEdges[end].report == e.report && kOutputEdges[end].needs == e.needs)
        ++end;
      v.push_back({i, end});
    }
    return v;
  }();
  return runs;
}

}  // namespace

void RunTracker::noteCharger(double t, const double* x, const PlantSignals& sig, bool on) {
  ChargeSummary& c = r_.summary.charge;
  chargerOn_ = on;
  if (on) {
    if (c.on_s < 0.0) c.on_s = t;
    c.off_s = -1.0;
    event(t, "charger", "enabled by the BMS");
    return;
  }
  const std::vector<double>& v = sig.cell_voltage_V;
  const int highest = static_cast<int>(std::max_element(v.begin(), v.end()) - v.begin());
  double soc = 0.0;
  for (size_t index : cellSocIndex_) soc += x[index];
  c.off_s = t;
  c.off_cell = highest + 1;
  c.off_cell_V = v[static_cast<size_t>(highest)];
  c.off_current_A = -sig.pack_current_A;
  c.off_soc_mean = soc / static_cast<double>(cellSocIndex_.size());
  event(t, "charger", "disabled by the BMS: " + chargeOffText(c, plant_.pack().parallel));
}

void RunTracker::outputEvents(double t, const bms::Outputs& out, bool report) {
  static_assert(kOutputEdgeCount <= sizeof lastOutput_ / sizeof lastOutput_[0], "RunTracker::lastOutput_ holds every row");
  uint64_t now[kOutputEdgeCount];  // each row's field, read once
  for (const EdgeRun& run : edgeRuns()) {
    const size_t i = run.begin, end = run.end;
    const OutputEdge& e = kOutputEdges[i];
    if (e.report != report || !rowApplies(e, hw_ != nullptr, r_.rec.has_balancing)) continue;
    if (!e.mask) {
      now[i] = e.read(out);
      const uint64_t before = lastOutput_[i];
      if ((now[i] != before || (first_ && e.on_first)) && (e.names == 0 || now[i] < e.names))
        event(t, e.kind, (e.shows_before && !first_ ? e.name(before) + " -> " : std::string()) + e.name(now[i]) +
                             (e.more ? e.more(cfg_, out, now[i]) : std::string()));
    } else {
      // Only the bits that changed in some row of the run are visited (in bit order, the
      // rows side by side), so an unchanged mask costs one compare.
      uint64_t changed = 0;
      for (size_t r = i; r < end; ++r) {
        now[r] = kOutputEdges[r].read(out);
        changed |= now[r] ^ lastOutput_[r];
      }
      if (e.names < 64) changed &= (uint64_t{1} << e.names) - 1;
      for (; changed; changed &= changed - 1) {
        const unsigned bit = static_cast<unsigned>(__builtin_ctzll(changed));
        for (size_t r = i; r < end; ++r) {
          const OutputEdge& m = kOutputEdges[r];
          const uint64_t b = uint64_t{1} << bit, on = now[r] & b, before = lastOutput_[r] & b;
          if (on && !before) event(t, m.kind, m.name(bit) + (m.more ? m.more(cfg_, out, bit) : std::string()));
          if (!on && before && m.falling) event(t, m.falling, m.name(bit));
        }
      }
    }
    for (size_t r = i; r < end; ++r) lastOutput_[r] = now[r];
  }
}

void RunTracker::tick(double t, const double* x, const PlantSignals& sig, const bms::Outputs& out) {
  Summary& sm = r_.summary;
  const size_t n = cellTemp_C_.size();  // the cells
  // One pass over the cells takes the tick's extremes of the voltages and temperatures
  // (for limits_, which then reads neither again, and for the summary below) and looks at
  // each SOC; the summary's lowest cell, hottest cell and first cell at its limit follow
  // from those extremes, with a second look at the cells only on the rare tick one of
  // them moves (the per-cell tests of each, some 15 instructions a cell, every tick).
  const double* cell_V = sig.cell_voltage_V.data();
  double* cell_C = cellTemp_C_.data();
  const size_t *tempIndex = cellTempIndex_.data(), *socIndex = cellSocIndex_.data();
  LimitWatch::Extremes volts, temps;
  for (size_t ci = 0; ci < n; ++ci) {
    const double T = x[tempIndex[ci]];
    cell_C[ci] = T;
    volts.take(cell_V[ci]);
    temps.take(T);
    const double soc = x[socIndex[ci]];
    if ((soc < 0.0) | (soc > 1.0)) noteSocRange(t, x, static_cast<int>(ci));  // one branch for the usual in-range SOC
  }
  // A new lowest (hottest) is the first cell at the tick's lowest (highest) value: the
  // cell a scan in order with a strict comparison keeps (Extremes skips a NaN, as that
  // comparison does).
  if (volts.lo < sm.min_cell_V) {
    sm.min_cell_V = volts.lo;
    sm.min_cell = firstCellAt(cell_V, volts.lo) + 1;
    sm.min_cell_time_s = t;
  }
  if (temps.hi > sm.max_temp_C) {
    sm.max_temp_C = temps.hi;
    sm.hottest_cell = firstCellAt(cell_C, temps.hi) + 1;
    sm.hottest_time_s = t;
  }
  // The first cell at or below its v_min_V, once: none can be while the tick's lowest
  // voltage is above the highest v_min_V.
  if (!sm.limit_reached && volts.lo <= highestMin_V_) {
    const double* cellMin_V = cellMin_V_.data();
    for (size_t ci = 0; ci < n; ++ci)
      if (cell_V[ci] <= cellMin_V[ci]) {
        noteLimit(t, x, static_cast<int>(ci));
        break;
      }
  }
  const LimitWatch::CellExtremes tickExtremes{volts, temps};

  const bool outputsMoved =
      core_ && (first_ || anyOutputChanged(out, lastOutput_, hw_ != nullptr, r_.rec.has_balancing));
  if (outputsMoved) outputEvents(t, out, false);  // the firmware's decisions: state, faults, relay command
  if (out.chargerEnable != chargerOn_ && r_.rec.has_charger) noteCharger(t, x, sig, out.chargerEnable);
  // A trip: the first tick the BMS holds the relay open on a latched fault (whether it
  // had closed it before or, as after a failed precharge, never got that far).
  if (!out.relayClose && out.faultLatched != 0 && !sm.tripped) {
    sm.tripped = true;
    sm.trip_time_s = t;
    std::string why;
    for (uint8_t i = 0; i < bms::kFaultCount; ++i)
      if (out.faultLatched & (1u << i)) why += (why.empty() ? "" : ", ") + std::string(bms::faultName(static_cast<bms::FaultId>(i)));
    sm.trip_reason = why;
    // An under-voltage trip is the pack's end of discharge: the weakest measured cell.
    if (!sm.limit_reached && (out.faultLatched & bms::faultBit(bms::FaultId::CellUnderVoltage))) {
      int weakest = 0;
      for (int c = 1; c < plant_.pack().cellCount(); ++c)
        if (sig.cell_voltage_V[static_cast<size_t>(c)] < sig.cell_voltage_V[static_cast<size_t>(weakest)]) weakest = c;
      noteLimit(t, x, weakest, true);
    }
  }
  if (hw_) {
    // Each called only when it has something to do: on the usual tick (no flag moved, no
    // new misuse) the two calls cost some 40 instructions for nothing.
    if (!sameEventFlags(hw_->status(), lastHw_)) hardwareChanged(t);
    for (size_t b = 0; b < misuseLogs_.size(); ++b)
      if (misuseSeen_[b] < misuseLogs_[b]->size()) {
        noteMisuse();  // every board's new entries
        break;
      }
  }
  if (outputsMoved) outputEvents(t, out, true);  // what it reports of the hardware: precharge, comm loss, balancing
  judgeEstimates(x, sig, out);
  limits_.tick(t, sig.cell_voltage_V, cellTemp_C_, sig.pack_current_A, out.faultActive, limitSink_, &tickExtremes);
  falseFaults_.tick(t, tickExtremes, sig.pack_current_A, sig.cell_voltage_V, cellTemp_C_, out.faultActive, falseFaultSink_);
  modelRange_.tick(temps.lo, temps.hi, cellTemp_C_, plant_.pack().parallel,
                   [this, t](const std::string& d) { event(t, "cell_model_range", d); });
  takeEnergyIn(x[plant_.stateSize() + kQuadLoadEnergy_J]);
  first_ = false;
  lastT_ = t;
  lastX_ = x;
}

// The load energy of one tick flows one way while its current keeps its sign: exact for
// a constant or stepped load; a ramp through 0 A inside a tick nets its two parts.
void RunTracker::takeEnergyIn(double loadEnergy_J) {
  const double step_J = loadEnergy_J - lastLoadEnergy_J_;
  lastLoadEnergy_J_ = loadEnergy_J;
  if (step_J < 0.0) energyIn_J_ -= step_J;
}

void RunTracker::hardwareChanged(double t) {
  if (!hw_) return;
  // What the hardware actually did (delays, weld, fuse, the monitor's FAULT line).
  const HardwareStatus& h = hw_->status();
  if (sameEventFlags(h, lastHw_)) return;  // no event (lastHw_ is read for these flags only)
  // Unrolled: each row's flag becomes a constant offset (once per tick, every tick).
#pragma GCC unroll 8
  for (const HardwareEdge& e : kHardwareEdges) {
    const bool now = h.*(e.flag), before = lastHw_.*(e.flag);
    if (now && !before) event(t, e.kind, e.rising);
    if (!now && before && e.falling) event(t, e.kind, e.falling);
  }
  // Why the monitor's line went up, as its parts report it (their latched protections).
  if (h.fault_line && !lastHw_.fault_line) {
    const std::string why = hw_->faultLineCause();
    if (!why.empty()) event(t, "monitor_protection", why);
  }
  if (h.active_safe_state != lastHw_.active_safe_state || h.active_isolated != lastHw_.active_isolated)
    event(t, "active_balancer", !h.active_safe_state ? "converters enabled"
                                : h.active_isolated ? "safe state: the BMS isolated the pack, converters off"
                                                    : "safe state: converters off");
  lastHw_ = h;
}

void RunTracker::pinsWritten(const std::vector<PinChange>& changes) {
  if (core_) return;  // the core's relay command is its table row's, at the tick
  for (const PinChange& c : changes)
    if (c.pins.relay != relayPin_) {
      relayPin_ = c.pins.relay;
      event(c.t_s, "relay", relayText(relayPin_));
    }
}

void RunTracker::firmwareTrip(double t, const std::string& reason) {
  Summary& sm = r_.summary;
  if (sm.tripped) return;
  sm.tripped = true;
  sm.trip_time_s = t;
  sm.trip_reason = reason;
}

void RunTracker::record(double t, const double* x, const PlantSignals& sig, const bms::Outputs& out) {
  recordSample({t, x, sig, out, plant_, cfg_, hw_, r_.rec, vehicle_}, r_.rec);
}

namespace {

// checkFinite's error, out of line: the check itself then needs no stack frame (the
// message's stream made it save six registers and set up 450 bytes, every tick).
[[noreturn]] __attribute__((noinline)) void throwDiverged(double t, int state) {
  std::ostringstream os;
  os << "the simulation diverged at t = " << t << " s (state " << state << " is not finite); "
     << "check the cell curves for the SOC range reached";
  throw std::runtime_error(os.str());
}

}  // namespace

void RunTracker::checkFinite(double t, const double* x, int n) const {
  // An infinity or NaN stays in a sum, and a sum of finite values is finite unless it
  // overflows: a finite sum clears the usual tick in one pass of adds (one instruction
  // per value pair, where x·0 summed took three); a sum that is not finite (a value that
  // is not, or huge finite ones) has the state looked at one by one.
  // (With SSE2 two values at a time in two sums, four a round: the order of the sum does
  // not matter here. Four sums cost a small state -- one cell's 11 values -- more in
  // set-up than they saved.)
  double probe = 0.0;
  int i = 0;
#if defined(__SSE2__)
  __m128d s0 = _mm_setzero_pd(), s1 = s0;
  for (; i + 4 <= n; i += 4) {
    s0 = _mm_add_pd(s0, _mm_loadu_pd(x + i));
    s1 = _mm_add_pd(s1, _mm_loadu_pd(x + i + 2));
  }
  if (i + 2 <= n) {
    s0 = _mm_add_pd(s0, _mm_loadu_pd(x + i));
    i += 2;
  }
  s0 = _mm_add_pd(s0, s1);
  probe = _mm_cvtsd_f64(s0) + _mm_cvtsd_f64(_mm_unpackhi_pd(s0, s0));
#endif
  for (; i < n; ++i) probe += x[i];
  if (std::isfinite(probe)) return;
  for (i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) throwDiverged(t, i);
}

RunResult RunTracker::finish(const double* q, const std::string& endReason) {
  Summary& sm = r_.summary;
  sm.duration_s = lastT_;
  static_assert(sizeof(r_.quad) / sizeof(r_.quad[0]) == kQuadCount, "RunResult::quad holds every quadrature");
  for (int i = 0; i < kQuadCount; ++i) r_.quad[i] = q[i];
  sm.charge_delivered_Ah = q[kQuadCharge_As] / 3600.0;
  sm.energy_delivered_Wh = q[kQuadLoadEnergy_J] / 3600.0;
  takeEnergyIn(q[kQuadLoadEnergy_J]);  // the last tick's, if the run ended after it
  sm.energy_in_Wh = energyIn_J_ / 3600.0;
  sm.heat_Wh = q[kQuadHeat_J] / 3600.0;
  sm.final_soc_min = INFINITY;
  sm.final_soc_max = -INFINITY;
  for (int c = 0; c < plant_.pack().cellCount(); ++c) {
    const double soc = plant_.cellStates(lastX_, c)[CellLayout::soc];
    sm.final_soc_min = std::min(sm.final_soc_min, soc);
    sm.final_soc_max = std::max(sm.final_soc_max, soc);
  }
  if (!sm.limit_reached) {  // no cell reached its limit: account at the end, against the lowest cell
    int lowest = 0;
    for (int c = 0; c < plant_.pack().cellCount(); ++c) {
      limitSoc_.push_back(plant_.cellStates(lastX_, c)[CellLayout::soc]);
      if (limitSoc_.back() < limitSoc_[static_cast<size_t>(lowest)]) lowest = c;
    }
    sm.limit_cell = lowest + 1;
    sm.limit_time_s = lastT_;
  }
  if (hw_) {  // writes a monitor IC ignored: each distinct one's count and last time
    noteMisuse();
    for (const MisuseReported& m : misuseEvents_)
      r_.events[m.event].detail = misuseDetail(m.board, hw_->registerMisuse(m.board).entries()[m.entry]);
  }
  if (hw_) {  // the series groups and thermistors the firmware never read
    const UnreadReport unread = hw_->unreadReport(lastT_);
    for (const std::string& d : unread.notes) event(lastT_, "monitor_unread", d);
    sm.unmonitored_groups = unread.groups;
  }
  for (const Event& e : r_.events) sm.relay_closed = sm.relay_closed || (e.kind == "relay_contact" && e.detail == "closed");
  sm.soc_error_coulomb = socErrorCoulomb_.stats();
  sm.soc_error_ekf = socErrorEkf_.stats();
  const StrandedEnergy se = strandedEnergy(plant_.pack(), limitSoc_, sm.limit_cell - 1);
  sm.energy_left_Wh = se.left_Wh;
  sm.energy_stranded_Wh = se.stranded_Wh;
  limits_.finish(lastT_, limitSink_);
  sm.limit_unseen_longest_s = limits_.longestUnseen_s();
  sm.limit_unseen_longest = limits_.longestUnseen();
  event(lastT_, "run", kRunEndEventPrefix + endReason);
  return std::move(r_);
}

namespace {

// judgeEstimates's pass over the groups: returns the sum of every cell's SOC (group by
// group, each group's cells in order) and, with kEkf (a valid EKF reading: decided once
// a tick, not per group), raises the largest group error
// (|EKF - true group mean|) and its group. kParallel: the cells per group when known at
// compile time (1: the loop and the division by 1 fold away; the same operations), 0:
// `parallel`. Locals instead of the summary's fields: its stores alias nothing read here.
template <int kParallel, bool kEkf>
double judgeGroups(const double* x, const size_t* socIndex, int series, int parallel, const uint16_t* group_permille,
                   double& errorMax, int& errorGroup) {
  const int p = kParallel > 0 ? kParallel : parallel;
  double total = 0.0, eMax = errorMax;
  int eGroup = errorGroup;
  for (int g = 0; g < series; ++g) {
    double sum = 0.0;
    for (int k = 0; k < p; ++k) sum += x[socIndex[static_cast<size_t>(g * p + k)]];
    total += sum;
    if (!kEkf) continue;
    const double e = std::fabs(group_permille[g] * 1e-3 - sum / p);
    if (e > eMax) {
      eMax = e;
      eGroup = g + 1;
    }
  }
  errorMax = eMax;
  errorGroup = eGroup;
  return total;
}

}  // namespace

void RunTracker::judgeEstimates(const double* x, const PlantSignals& sig, const bms::Outputs& out) {
  const bms::Telemetry& tm = out.telemetry;
  if (!tm.socCoulombValid && !tm.socEkfValid) return;
  Summary& sm = r_.summary;
  // One pass over the cells: each group's true SOC against its EKF, and the pack mean.
  const int series = plant_.pack().series, parallel = plant_.pack().parallel;
  const size_t* socIndex = cellSocIndex_.data();
  double& eMax = sm.soc_error_ekf_group_max;
  int& eGroup = sm.soc_error_ekf_group;
  const uint16_t* ekf = tm.socGroup_permille;
  const double total =
      parallel == 1 ? (tm.socEkfValid ? judgeGroups<1, true>(x, socIndex, series, 1, ekf, eMax, eGroup)
                                      : judgeGroups<1, false>(x, socIndex, series, 1, ekf, eMax, eGroup))
                    : (tm.socEkfValid ? judgeGroups<0, true>(x, socIndex, series, parallel, ekf, eMax, eGroup)
                                      : judgeGroups<0, false>(x, socIndex, series, parallel, ekf, eMax, eGroup));
  const double truth = total / plant_.pack().cellCount();
  if (tm.socCoulombValid) socErrorCoulomb_.add(tm.socCoulomb, truth);
  if (tm.socEkfValid) socErrorEkf_.add(tm.socEkf, truth);
  sm.capacity_estimate_Ah = tm.capacityEstimate_mAh * 1e-3;
  if (tm.socCoulombValid) {  // the display runs from the same complete reading
    // The true bars again only when their input moved (a whole mV: most ticks it has not).
    const uint16_t at_mV = trueDisplay_mV(sig);
    if (at_mV != displayAt_mV_) {
      displayAt_mV_ = at_mV;
      displayBars_ = bms::socDisplayBars(cfg_.soc, at_mV);
    }
    const int diff = static_cast<int>(displayBars_) - static_cast<int>(tm.socDisplayBars);
    sm.display_bars_hidden_max = std::max(sm.display_bars_hidden_max, diff);
    sm.display_bars_extra_max = std::max(sm.display_bars_extra_max, -diff);
  }
}

}  // namespace packsim

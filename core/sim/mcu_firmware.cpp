#include "core/sim/mcu_firmware.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include <bms/bms_balance.hpp>
#include <bms/bms_firmware.hpp>

#include "core/firmware/pin_timeline.hpp"
#include "models/afe/byte_copy.hpp"

namespace packsim {

namespace {

// The pack's balancing status from a member board's and the rest's: each board decides for
// its own cells (the host shares the pack's range), so the host alone may say "balanced"
// while a member bleeds. A board balancing makes the pack balancing; else a hot board
// pauses it; else "balanced" over "not allowed" over "disabled".
uint8_t packBalanceStatus(uint8_t pack, uint8_t board) {
  using B = bms::BalanceStatus;
  const auto rank = [](uint8_t v) {
    switch (static_cast<B>(v)) {
      case B::Balancing: return 4;
      case B::BoardHot: return 3;
      case B::Balanced: return 2;
      case B::NotAllowed: return 1;
      default: return 0;
    }
  };
  return rank(board) > rank(pack) ? board : pack;
}

}  // namespace

McuFirmware::McuFirmware(const Scenario& s, const bms::Config& cfg, HardwareSim& hw, RunTracker& tracker)
    : tracker_(tracker), hw_(hw), library_(s.bms.firmware.library), nominal_V_(s.hardware.supply_nominal_V),
      brownout_V_(s.hardware.supply_brownout_V), tickFor_s_(s.bms.tick_s), coreElf_(s.bms.firmware.library_path) {
  const std::vector<MonitorBoard>& boards = hw.boards();
  if (boards.size() == 1) {
    FirmwareBoard board{hw.monitorBuses(), hw.mcuThermistorCount()};
    if (s.hardware.can_alone) {  // a bus to the vehicle / charger
      can_ = std::make_unique<CanBus>(2, s.hardware.can_bitrate_bps);
      can_->trace(true);
      board.can = can_.get();
      board.canNode = 0;
      aloneCan_ = true;
      scripted_ = s.hardware.can_frames;
      for (const ScriptedCanFrame& f : scripted_) nextScripted_s_.push_back(f.at_s);
    }
    if (library_) {
      hosts_.push_back(std::make_unique<FirmwareHost>(s.bms.firmware, board, s.bms.tick_s, *this));
    } else if (s.bms.firmware.isTarget()) {  // packsim's core as ARM code (packsim_core_cm4.elf), the same image
      FirmwareSettings core = s.bms.firmware;
      core.config = coreImage(cfg);
      hosts_.push_back(std::make_unique<FirmwareHost>(core, board, s.bms.tick_s, *this));
      targetRam_ = std::make_unique<bms::CoreFirmwareRam>();
    } else {
      hosts_.push_back(std::make_unique<FirmwareHost>(bms::coreFirmware(), coreImage(cfg), board, s.bms.tick_s, *this));
    }
    return;
  }
  // One MCU per board on the shared CAN bus, each flashed for its board.
  const int n = static_cast<int>(boards.size());
  can_ = std::make_unique<CanBus>(n, s.hardware.can_bitrate_bps);
  memberPins_.resize(boards.size());
  for (const MonitorBoard& b : boards) {
    bms::Config c = makeBmsConfig(boardScenario(s, b));
    c.pack = bms::PackConfig{static_cast<uint8_t>(b.index), static_cast<uint8_t>(n)};
    FirmwareBoard board{hw.monitorBuses(b.index), static_cast<int>(b.mcuChannels.size()), b.index == 0, can_.get(),
                        b.index};
    hosts_.push_back(std::make_unique<FirmwareHost>(bms::coreFirmware(), coreImage(c), board, s.bms.tick_s, *this));
  }
}

void McuFirmware::injectScripted(double before_s) {
  for (size_t i = 0; i < scripted_.size(); ++i) {
    const ScriptedCanFrame& fr = scripted_[i];
    double& next = nextScripted_s_[i];
    while (next < before_s && next <= fr.until_s + 1e-12) {
      can_->inject(1, next, fr.id, fr.data.data(), static_cast<uint8_t>(fr.data.size()));
      if (!(fr.period_s > 0.0)) {
        next = std::numeric_limits<double>::infinity();
        break;
      }
      next += fr.period_s;
    }
  }
}

std::vector<CanTraceRow> McuFirmware::takeCanTrace() {
  std::vector<CanTraceRow> rows;
  if (!aloneCan_) return rows;
  can_->runUntil(std::numeric_limits<double>::infinity());  // every frame queued in the run's ticks
  for (const CanBus::TraceRow& t : can_->takeTrace()) {
    CanTraceRow r;
    r.time_s = t.start_s;
    r.end_s = t.end_s;
    r.out = t.from == 0;
    r.id = static_cast<int>(t.id);
    r.dlc = t.len;
    r.lost = t.lost;
    char hex[4];
    for (uint8_t k = 0; k < t.len; ++k) {
      std::snprintf(hex, sizeof hex, k ? " %02X" : "%02X", t.data[k]);
      r.data += hex;
    }
    rows.push_back(r);
  }
  return rows;
}

const bms::Outputs& McuFirmware::decide(double t_s, const bms::Inputs& in, bms::Outputs& out, const HardwareFaults& f) {
  if (aloneCan_) injectScripted(t_s + tickFor_s_);
  // Every MCU of the pack is on the BMS's 12 V rail: below the brown-out threshold each
  // is held in reset, and boots at the first tick the rail is back.
  if (f.supply_V >= 0.0 && f.supply_V < brownout_V_) {
    char why[160];
    std::snprintf(why, sizeof why, "brown-out: the %g V supply at %.2f V, below the MCU's %.2f V brown-out threshold",
                  nominal_V_, f.supply_V, brownout_V_);
    hosts_.front()->holdInReset(t_s, why, out);
    for (size_t b = 1; b < hosts_.size(); ++b) {
      hosts_[b]->holdInReset(t_s, std::string(why) + " (board " + std::to_string(b + 1) + ")", memberPins_[b]);
      hosts_[b]->takePinChanges();
    }
    return *(decided_ = library_ ? &out : &probe(out));
  }
  if (!f.host_dead) hosts_.front()->step(t_s, in, out);
  for (size_t b = 1; b < hosts_.size(); ++b) {
    if (!(f.dead_boards & (1u << b))) hosts_[b]->step(t_s, in, memberPins_[b]);
    hosts_[b]->takePinChanges();  // a member's port pins are not wired to the pack
  }
  if (library_)
    decided_ = &out;
  else if (!f.host_dead)
    decided_ = &probe(out);
  else if (!decided_)  // a hung host: what it decided last (its RAM has not changed since)
    decided_ = &out;
  return *decided_;
}

// The pack host's outputs with each board's own arrays at their pack positions.
const bms::Outputs& McuFirmware::probe(bms::Outputs& out) {
  if (!hosts_.front()->ram()) return out;
  if (const TargetFirmware* t = hosts_.front()->target()) {
    // The core's RAM on the virtual MCU, read as a debugger reads it. Its layout is the
    // host build's (the same sources; ILP32 and LP64 lay these structs out alike, no
    // pointers in them): checked by size, the image's own tag and size at init.
    if (t->instanceBytes() != sizeof(bms::CoreFirmwareRam))
      throw std::runtime_error(coreElf_ + " was built from other sources than this packsim: its core's RAM is " +
                               std::to_string(t->instanceBytes()) + " bytes, this packsim's " +
                               std::to_string(sizeof(bms::CoreFirmwareRam)) +
                               " (rebuild it: cmake --build build --target packsim_core_cm4)");
    if (!t->readInstanceRam(targetRam_.get(), sizeof(bms::CoreFirmwareRam))) return out;
    out = targetRam_->out;
    return out;  // one board only in target mode (the loader refuses several)
  }
  const bms::Outputs& ram = bms::coreFirmwareOutputs(hosts_.front()->ram());
  if (hosts_.size() == 1) {
    // Read in place. The host reads and writes only the pins of `out` (GPIO, DAC,
    // resets): they start the next tick as a whole copy would have left them.
    applyPins(out, pinsOf(ram));
    return ram;
  }
  // A kilobyte and more each tick: through the library's memcpy, not the inline rep movsq
  // GCC makes of the struct assignment (models/afe/byte_copy.hpp).
  static_assert(std::is_trivially_copyable_v<bms::Outputs>);
  copyBytes(&out, &ram, sizeof(bms::Outputs));
  bms::Telemetry& tm = out.telemetry;
  const bms::Telemetry host = tm;
  for (uint32_t& w : out.balanceMask) w = 0;
  for (const MonitorBoard& b : hw_.boards()) {
    const FirmwareHost& h = *hosts_[static_cast<size_t>(b.index)];
    if (!h.ram()) continue;
    const bms::Outputs& o = b.index == 0 ? out : bms::coreFirmwareOutputs(h.ram());
    const bms::Telemetry& bt = b.index == 0 ? host : o.telemetry;
    const uint32_t* mask = b.index == 0 ? bms::coreFirmwareOutputs(h.ram()).balanceMask : o.balanceMask;
    if (b.index != 0) out.balanceStatus = packBalanceStatus(out.balanceStatus, o.balanceStatus);
    for (int i = 0; i < b.cells; ++i) {
      const int g = b.firstCell + i;
      tm.cellVoltage_mV[g] = bt.cellVoltage_mV[i];
      tm.socGroup_permille[g] = bt.socGroup_permille[i];
      if (bms::balanceBit(mask, static_cast<uint16_t>(i))) out.balanceMask[g / 32] |= 1u << (g % 32);
    }
    size_t j = 0;  // the board's channels in its own order: inputs, then (pack host) its ADC
    for (const std::vector<int>* list : {&b.afeChannels, &b.mcuChannels})
      for (int k : *list) tm.temperature_dC[k] = bt.temperature_dC[j++];
    for (int d = 0; d < b.devices; ++d) {
      tm.commBad[b.firstDevice + d] = bt.commBad[d];
      tm.lastResult[b.firstDevice + d] = bt.lastResult[d];
    }
  }
  return out;
}

bool McuFirmware::anyDead() const {
  for (const auto& h : hosts_)
    if (h->dead()) return true;
  return false;
}

double McuFirmware::worstTaskTime_s(int task) const {
  double worst = 0.0;
  for (const auto& h : hosts_) worst = std::max(worst, h->worstTaskTime_s(task));
  return worst;
}

void McuFirmware::enforceBudgets(bool on) {
  for (auto& h : hosts_) h->enforceBudgets(on);
}

std::string McuFirmware::status() const {
  if (library_) return hosts_.front()->status();
  for (size_t b = 0; b < hosts_.size(); ++b)
    if (hosts_[b]->dead())
      return (hosts_.size() > 1 ? "board " + std::to_string(b + 1) + " " : std::string()) + hosts_[b]->status();
  return "";
}

}  // namespace packsim

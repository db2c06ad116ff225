#include "core/sim/hw_sensors.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "models/random/random.hpp"
#include "models/sensors/round_half_away.hpp"

namespace packsim {

namespace {

static_assert(sizeof(ChannelError) == 2 * sizeof(double) && std::is_trivially_copyable_v<ChannelError>,
              "ChannelError compared as its bytes: its two doubles, no padding");

// Whether a board's `injected` channel errors from `now` (of its `cells`) are, bit for bit,
// those `given` holds (the last tick's; -0.0 and 0.0 differ here: both reach the channel's
// sums, where they need not give the same bits). Fewer than all cells named: never.
bool sameChannelErrors(const std::vector<ChannelError>& given, const ChannelError* now, size_t injected, size_t cells) {
  if (injected != cells || given.size() != cells) return false;
  // (a cell's 16 bytes per step, no early exit: a few cells, where memcmp's call and a
  // loop of words each cost more)
  const unsigned char* a = reinterpret_cast<const unsigned char*>(given.data());
  const unsigned char* b = reinterpret_cast<const unsigned char*>(now);
  const size_t bytes = cells * sizeof(ChannelError);
#if defined(__SSE2__)
  __m128i diff = _mm_setzero_si128();
  for (size_t i = 0; i < bytes; i += 16)
    diff = _mm_or_si128(diff, _mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(a + i)),
                                            _mm_loadu_si128(reinterpret_cast<const __m128i*>(b + i))));
  return _mm_movemask_epi8(_mm_cmpeq_epi8(diff, _mm_setzero_si128())) == 0xFFFF;
#else
  return bytes == 0 || std::memcmp(a, b, bytes) == 0;
#endif
}

}  // namespace

HwSensors::HwSensors(const Scenario& s, const Plant& plant)
    : s_(s), plant_(plant), boards_(monitorBoards(s.hardware, s.pack.series)), currentAdc_(s.hardware.current_sense.channel()) {
  // One register-level stack per monitor board; board 0 draws from the run's seed (a
  // single-board pack as ever), the others from their own streams.
  for (const MonitorBoard& b : boards_) {
    MonitorConfig a = s.hardware.afe;
    a.devices = b.devices;
    const uint64_t seed = b.index == 0 ? s.run.seed : deriveSeed(s.run.seed, static_cast<uint64_t>(RngStream::MonitorBoard) + static_cast<uint64_t>(b.index));
    chains_.push_back(std::make_unique<MonitorChainPath>(a, b.cells, seed));
    truths_.push_back(chains_.back()->makeTruth());
    channelsGiven_.emplace_back();
    if (s.output.bus_trace) chains_.back()->traceInto(busTrace_, b.index);
  }
  mcuTherm_.resize(boards_.front().mcuChannels.size());
  // The node each thermistor channel reads: its group's first cell, the FETs' node, its
  // balancing board's node.
  for (const ThermistorChannel& ch : s.hardware.thermistors.channels) {
    const int node = ch.site == ThermSite::Cell  ? ch.group * plant.pack().parallel
                     : ch.site == ThermSite::Fet ? plant.thermal().find(ch.node)
                                                      : plant.boardNodeOf(ch.board);
    thermNode_.push_back(static_cast<size_t>(node));
  }
}

int HwSensors::boardOfGroup(int g) const {
  for (const MonitorBoard& b : boards_)
    if (g < b.firstCell + b.cells) return b.index;
  return static_cast<int>(boards_.size()) - 1;
}

bool HwSensors::balancing(int g) const {
  const MonitorBoard& b = boards_[static_cast<size_t>(boardOfGroup(g))];
  return chains_[static_cast<size_t>(b.index)]->balancing(g - b.firstCell);
}

double HwSensors::balancingDuty(int g, double t0, double t1) const {
  const MonitorBoard& b = boards_[static_cast<size_t>(boardOfGroup(g))];
  return chains_[static_cast<size_t>(b.index)]->balancingDuty(g - b.firstCell, t0, t1);
}

void HwSensors::balancingSwitches(double t0, double t1, uint8_t* on, double* duty) const {
  const int series = s_.pack.series;
  int covered = 0;  // the boards hold the series groups in order, each after the one before
  for (const MonitorBoard& b : boards_) {
    if (b.firstCell != covered || covered + b.cells > series) break;
    chains_[static_cast<size_t>(b.index)]->balancingSwitches(t0, t1, on + b.firstCell, duty + b.firstCell);
    covered += b.cells;
  }
  for (int g = covered; g < series; ++g) {  // any group no board holds in order: as asked one by one
    on[g] = balancing(g) ? 1 : 0;
    duty[g] = on[g] ? balancingDuty(g, t0, t1) : 1.0;
  }
}

bool HwSensors::faultLine() const {
  for (const auto& c : chains_)
    if (c->faultLine()) return true;
  return false;
}

std::string HwSensors::faultLineCause() const {
  std::string out;
  for (size_t b = 0; b < chains_.size(); ++b) {
    const std::string why = chains_[b]->faultLine() ? chains_[b]->faultCause() : "";
    if (why.empty()) continue;
    appendListed(out, (chains_.size() > 1 ? "board " + std::to_string(b + 1) + " " : std::string()) + why, "; ");
  }
  return out;
}

void HwSensors::sample(double t, const PlantSignals& sig, const PlantSignals& unloaded, const HardwareFaults& f,
                       double bus_V, bool relayAux, Rng& rng, bms::Inputs& in) {
  const HardwareConfig& hw = s_.hardware;
  auto thermFault = [&](size_t k) {
    return k < f.thermistor.size() ? f.thermistor[k] : ThermistorFault::None;
  };
  auto thermTemp = [&](size_t k) { return sig.node_temp_C[thermNode_[k]]; };
  // Each board's stack: its cells at the pins, each device's die on the balancing board
  // of its first cell (or the ambient air without one), its thermistor inputs, its
  // devices' comm faults; a broken link cuts off the devices above it on that board.
  for (const MonitorBoard& b : boards_) {
    MonitorTruth& tr = truths_[static_cast<size_t>(b.index)];
    tr.host_opens_balancing = s_.bms.balancing.measure_paused;
    const size_t first = static_cast<size_t>(b.firstCell), cells = static_cast<size_t>(b.cells);
    tr.cell_V = sig.group_voltage_V.data() + first;  // views: the devices copy them into their pins
    tr.cell_unloaded_V = unloaded.group_voltage_V.data() + first;
    // Injected channel errors where the faults name the channel (none: 0). The same bits
    // as the last tick's (the usual tick): the truth holds them already, and says so (the
    // chain hands them on only when they change).
    const size_t injected = f.cell_channel.size() > first ? std::min(cells, f.cell_channel.size() - first) : 0;
    std::vector<ChannelError>& given = channelsGiven_[static_cast<size_t>(b.index)];
    tr.channel_errors_unchanged = sameChannelErrors(given, f.cell_channel.data() + first, injected, cells);
    if (!tr.channel_errors_unchanged) {
      for (size_t i = 0; i < injected; ++i) {
        tr.cell_gain_error[i] = f.cell_channel[first + i].gain_error;
        tr.cell_offset_V[i] = f.cell_channel[first + i].offset_V;
      }
      for (size_t i = injected; i < cells; ++i) tr.cell_gain_error[i] = tr.cell_offset_V[i] = 0.0;
      given.assign(f.cell_channel.data() + first, f.cell_channel.data() + first + injected);
    }
    for (size_t d = 0; d < tr.board_C.size(); ++d) {
      const int node = plant_.boardNodeOfGroup(b.firstCell + static_cast<int>(d) * hw.afe.cells_per_device);
      tr.board_C[d] = node >= 0 ? sig.node_temp_C[static_cast<size_t>(node)] : sig.ambient_C;
    }
    for (size_t j = 0; j < tr.therm_C.size(); ++j) {
      const bool used = j < b.afeChannels.size();
      tr.therm_C[j] = used ? thermTemp(static_cast<size_t>(b.afeChannels[j])) : 25.0;
      tr.therm_fault[j] = used ? thermFault(static_cast<size_t>(b.afeChannels[j])) : ThermistorFault::None;
    }
    const int cut = f.broken_link_above - b.firstDevice;  // local index of the last device still linked
    const bool cutHere = f.broken_link_above >= 0 && cut >= 0 && cut < b.devices;
    for (size_t d = 0; d < tr.comm.size(); ++d) {
      const size_t gd = static_cast<size_t>(b.firstDevice) + d;
      // (a reference to either: a temporary of the ?: was built bytewise on the stack and
      // read back whole, a store-forwarding stall each tick)
      tr.comm[d] = gd < f.device.size() ? f.device[gd] : kHealthyDevice;
      if (cutHere && static_cast<int>(d) > cut && f.broken_link_byte >= 0) tr.comm[d].stuck_byte = f.broken_link_byte;
    }
    tr.broken_link_above = cutHere && f.broken_link_byte < 0 ? cut : -1;
    tr.current_A = sig.pack_current_A;
    chains_[static_cast<size_t>(b.index)]->update(t, tr);  // the board's host reads it over its bus
  }

  // Thermistors beyond the monitor inputs sit on the pack host's own ADC.
  const std::vector<int>& mcu = boards_.front().mcuChannels;
  for (size_t j = 0; j < mcu.size(); ++j) {
    const size_t k = static_cast<size_t>(mcu[j]);
    const ThermistorFault sf = thermFault(k);
    const int64_t code = sf == ThermistorFault::Open    ? hw.thermistor.fullScaleCode()
                         : sf == ThermistorFault::Short ? 0
                                                    : mcuTherm_[j].code(hw.thermistor, thermTemp(k), rng);
    in.mcuThermistorCode[j] = static_cast<uint16_t>(code);
  }
  const double senseOffset_A = f.current_sensor_offset_A + f.current_sensor_drift_A_per_s * t;
  in.currentCode = static_cast<int32_t>(currentAdc_.convert(sig.pack_current_A + senseOffset_A, rng));
  in.busVoltageCode = static_cast<uint16_t>(hw.bus_adc.convert(bus_V, rng));
  in.eSwitchInternal = f.estop_internal_pulled;
  in.eSwitchExternal = f.estop_external_pulled;
  in.relayAux = relayAux;
  in.monitorFaultPin = faultLine();
  in.chargerPresent = s_.bms.charger_present;
  in.runRequest = s_.bms.run_request && !f.key_off;
  in.resetRequest = f.reset_requested;
  in.now_ms = static_cast<uint32_t>(roundHalfAway(t * 1e3));  // std::llround, inline
}

// The monitor ICs' thermistor bias, from each device's top cell while it is switched on.
bool HwSensors::applyBiasOn(PlantInputs& pin) const {
  bool changed = pin.bias_A.size() != static_cast<size_t>(s_.pack.series);
  if (changed) pin.bias_A.assign(static_cast<size_t>(s_.pack.series), 0.0);
  for (const MonitorBoard& b : boards_) {
    const MonitorChainPath& c = *chains_[static_cast<size_t>(b.index)];
    for (int d = 0; d < c.devices(); ++d) {
      const size_t g = static_cast<size_t>(b.firstCell + c.topCell(d));
      const double i = c.thermistorBias_A(d);
      changed = changed || pin.bias_A[g] != i;
      pin.bias_A[g] = i;
    }
  }
  return changed;
}

}  // namespace packsim

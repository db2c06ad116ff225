// The recorded time series as one table: one row per result channel (its HDF5 path,
// unit, second axis, long name, the Recording vector that holds it and how one sample
// of it is taken). The recorder (run_tracker), the HDF5 writer and its netCDF layout
// (core/io), the Python zero-copy views (python/src/result_arrays.cpp) and the docs
// test (tests/python/test_results_doc.py) all iterate this table, so adding a channel
// is one row here plus its vector in Recording (result.hpp) and its line in
// docs/results.md. See docs/architecture.md, "How to add a result channel".
#pragma once
#include <bms/bms_hal.hpp>

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "core/sim/result.hpp"

namespace bms {
struct Config;
}

namespace packsim {

class Plant;
class HardwareSim;
struct PlantSignals;

// Everything one sample is taken from: the truth at t (state vector and the plant's
// signals), what the firmware saw and decided, and the switching hardware.
struct ChannelSample {
  double t_s;
  const double* x;
  const PlantSignals& sig;
  const bms::Outputs& out;
  const Plant& plant;
  const bms::Config& cfg;
  const HardwareSim* hw;  // set whenever a channel with Presence::Hardware is recorded
  const Recording& rec;   // its sizes (thermistors, devices)
  const VehicleSample* vehicle = nullptr;  // set whenever a channel with Presence::Vehicle is recorded
};

// The second axis of a [samples, k] channel; None: a [samples] channel.
enum class Axis : uint8_t { None, Cell, Series, Thermistor, Device, TelemetryByte };

// Which runs record a channel (Recording's has_* flags).
enum class Presence : uint8_t { Always, Hardware, Balancing, BalancingHardware, Board, ActiveBalancer, Charger, Vehicle };

// Where a channel's values live and how one sample of them is appended (one value, or
// one per entry of its axis).
template <typename T>
struct Column {
  std::vector<T> Recording::*data;
  void (*fill)(const ChannelSample& s, std::vector<T>& v);
};
using AnyColumn =
    std::variant<Column<double>, Column<uint8_t>, Column<int16_t>, Column<uint16_t>, Column<int32_t>, Column<uint32_t>>;

// One attribute a channel carries besides units and long_name (an enumeration's
// `names`, a `meaning`, a `layout`).
struct ChannelAttr {
  const char* name = nullptr;  // nullptr: none
  std::string (*value)(const Recording& rec) = nullptr;
};

struct ResultChannel {
  const char* path;       // HDF5 path; the Python key is the path without the leading '/'
  const char* units;      // the HDF5 `units` attribute; nullptr for flags, enumerations, bit sets
  Axis axis;
  Presence presence;
  const char* long_name;  // the HDF5 `long_name` attribute (netCDF)
  AnyColumn column;
  ChannelAttr attr;
};

// Every channel, in the order the result file lists them.
const std::vector<ResultChannel>& resultChannels();
// The channel at `path` ("/truth/cell_voltage_V"); nullptr if there is none.
const ResultChannel* findResultChannel(const std::string& path);

bool isRecorded(const ResultChannel& c, const Recording& rec);
// Length of the second axis in this recording (0 for Axis::None).
size_t axisLength(Axis axis, const Recording& rec);
// The netCDF dimension name of the second axis ("cell", "series", ...).
const char* axisName(Axis axis);
// NumPy's name of the channel's element type ("float64", "uint8", ...).
const char* dtypeName(const ResultChannel& c);
// The decimal places a floating-point channel is stored to, by its unit: V 7 (0.1 µV),
// A, W and degC 6, SOC (1) and Ah 9; -1: stored exactly (time, integer channels). The
// file keeps float64 and says the step in a `resolution` attribute; far below any
// measurement and the solvers' tolerance, it halves the bytes of a run's truth.
int storedDecimals(const ResultChannel& c);

// The bars the SOC display would show if it read the true open-circuit voltage (mean
// cell): the truth the firmware's display is judged against.
uint8_t trueDisplayBars(const bms::Config& cfg, const PlantSignals& sig);
// Its input: the mean cell open-circuit voltage in whole mV, as the display reads it.
uint16_t trueDisplay_mV(const PlantSignals& sig);

// Appends one sample of every channel this recording holds.
void recordSample(const ChannelSample& s, Recording& rec);

}  // namespace packsim

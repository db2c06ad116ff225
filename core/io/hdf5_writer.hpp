// Writes one run to an HDF5 file:
//
//   /                 attrs: packsim_version, scenario_name, scenario_yaml, seed, solver,
//                            tick_s, sign_convention
//   /time_s           [n]
//   /truth/…          per-cell arrays [n, cells] and pack voltage/current [n] (SI units)
//   /measured/…       what the BMS core saw, in its units (mV, deci-degC, mA)
//   /bms/…            state, fault bits, relay and FET commands [n]
//   /events           table (time_s, kind, detail)
//   /bus_trace        table (time_s, bus, direction, count, bytes, what); output.bus_trace only
//   /summary          attrs: the run summary
//   /inputs           a batch case only (drawn != nullptr): the random inputs as drawn,
//                     per-cell datasets and their figures as attrs (core/batch/drawn_inputs.hpp)
//
// Laid out for netCDF tools (core/io/hdf5_layout.hpp): dimension scales, long_name and
// units attributes, datasets chunked and compressed with deflate + shuffle.
//
// The file is written under a temporary name of its own process and renamed when
// complete, so a failed run never leaves a partial result behind and two runs writing
// the same file end with one complete file (the last one renamed). Object timestamps are off: the same run
// gives the same bytes.
#pragma once
#include <string>

#include "core/batch/drawn_inputs.hpp"
#include "core/scenario/scenario.hpp"
#include "core/sim/result.hpp"

namespace packsim {

// Throws Interrupted (core/sim/stop_signal.hpp) instead of renaming when a stop signal
// arrived while writing, and std::runtime_error when a write or the close fails (disk
// full); the temporary file is removed in both cases.
void writeResultHdf5(const std::string& path, const Scenario& s, const RunResult& r,
                     const DrawnInputs* drawn = nullptr);
// The same file built in memory (HDF5's core driver, nothing on disk; no compression:
// it is read back at once), as bytes: what packsim.run() reads its attributes and
// events from.
std::string resultHdf5Image(const Scenario& s, const RunResult& r);

// `<path>.tmp.<pid>.<random>`: the temporary name one process writes a result under
// before renaming it to `path` (two runs writing the same result never share one).
std::string uniqueTemporaryName(const std::string& path);

// What is at a path now (identity and last change), to tell whether another process
// replaced a result file while this run was running.
struct ResultFileStamp {
  bool exists = false;
  unsigned long long device = 0, inode = 0;
  long long size = 0, mtime_ns = 0;
  bool operator==(const ResultFileStamp& o) const {
    return exists == o.exists && device == o.device && inode == o.inode && size == o.size && mtime_ns == o.mtime_ns;
  }
  bool operator!=(const ResultFileStamp& o) const { return !(*this == o); }
};
ResultFileStamp resultFileStamp(const std::string& path);

// Checks before a run that a result can be written at `path`: not an existing directory
// or device, its folder creatable and writable (a probe file is created and removed).
// Throws std::invalid_argument "cannot write the result file '<path>': <reason>".
void checkResultPathWritable(const std::string& path);

}  // namespace packsim

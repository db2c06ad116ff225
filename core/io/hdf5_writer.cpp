#include "core/io/hdf5_writer.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/scenario/bms_setting_table.hpp"
#include "core/sim/stop_signal.hpp"

#include <bms/bms_core.hpp>
#include <bms/bms_faults.hpp>
#include <bms/bms_telemetry.hpp>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <random>
#include <dirent.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>
#include <stdexcept>
#include <variant>
#include <vector>

#include "core/io/hdf5_layout.hpp"
#include "core/sim/result_channels.hpp"
#include "core/sim/summary_fields.hpp"
#include "core/version.hpp"

namespace packsim {

namespace {

// RAII for one hid_t with its matching close function.
// HDF5 closes every open file again at exit; after a close that failed (a full disk)
// that second close dereferences freed state and crashes (libhdf5 1.10). Every file is
// closed explicitly here, so the library's exit hook is switched off before first use.
const bool kNoHdf5ExitHook = (H5dont_atexit(), true);

class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const char* what) : id_(id), close_(close) {
    if (id_ < 0) throw std::runtime_error(std::string("HDF5: cannot create ") + what);
  }
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  // Closes now and reports a failed close (the last writes of a file happen here).
  void close(const char* what) {
    const hid_t id = id_;
    id_ = -1;
    if (close_(id) < 0) throw std::runtime_error(std::string("HDF5: cannot finish writing ") + what);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void checked(herr_t e, const std::string& what) {
  if (e < 0) throw std::runtime_error("HDF5: failed to write " + what);
}

template <typename T>
hid_t nativeType();
template <> hid_t nativeType<double>() { return H5T_NATIVE_DOUBLE; }
template <> hid_t nativeType<uint8_t>() { return H5T_NATIVE_UINT8; }
template <> hid_t nativeType<int16_t>() { return H5T_NATIVE_INT16; }
template <> hid_t nativeType<uint16_t>() { return H5T_NATIVE_UINT16; }
template <> hid_t nativeType<int32_t>() { return H5T_NATIVE_INT32; }
template <> hid_t nativeType<uint32_t>() { return H5T_NATIVE_UINT32; }

// Rows per chunk: about 16 Ki values per chunk, whole rows.
hsize_t chunkRows(size_t rows, size_t cols) {
  const size_t perRow = cols == 0 ? 1 : cols;
  const size_t r = std::max<size_t>(1, 16384 / perRow);
  return static_cast<hsize_t>(std::min(rows, r));
}

// A result file holds finite numbers only (docs/results.md): a channel value or an
// attribute that is not is refused, naming the channel and the time (then nothing is
// written). A first line of defence is the scenario's ranges (docs/scenario.md) and the
// integrators' state check; this catches what got past them.
struct NonFiniteValue : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string sampleTime(const std::vector<double>* time_s, size_t row) {
  std::ostringstream os;
  os.precision(12);
  if (time_s && row < time_s->size()) os << "at t = " << (*time_s)[row] << " s";
  else os << "in row " << row;
  return os.str();
}

template <typename T>
void requireFinite(const std::string& name, const std::vector<T>& data, size_t cols,
                   const std::vector<double>* time_s) {
  if constexpr (std::is_floating_point_v<T>) {
    const auto bad = std::find_if(data.begin(), data.end(), [](T v) { return !std::isfinite(v); });
    if (bad == data.end()) return;
    const size_t k = static_cast<size_t>(bad - data.begin());
    const size_t row = cols == 0 ? k : k / cols;
    std::ostringstream os;
    os << "the channel " << name;
    if (cols > 0) os << "[" << k % cols << "] (0-based column)";
    os << " is " << *bad << " " << sampleTime(time_s, row)
       << ": a result holds finite numbers only (a value out of any physical range; check the scenario's loads, "
          "faults and cell curves)";
    throw NonFiniteValue(os.str());
  }
}

class Writer {
 public:
  Writer(hid_t file, bool compress, const std::vector<double>* time_s = nullptr)
      : file_(file), compress_(compress), time_s_(time_s) {
    dcpl_ = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_obj_track_times(dcpl_, 0);
    gcpl_ = H5Pcreate(H5P_GROUP_CREATE);
    H5Pset_obj_track_times(gcpl_, 0);
  }
  ~Writer() {
    H5Pclose(dcpl_);
    H5Pclose(gcpl_);
  }

  void group(const char* name) {
    Handle g(H5Gcreate2(file_, name, H5P_DEFAULT, gcpl_, H5P_DEFAULT), H5Gclose, name);
  }

  // decimals >= 0: a float channel stored to that many decimal places (HDF5's
  // scale-offset filter, then shuffle and deflate); -1: every bit as written.
  template <typename T>
  void dataset(const std::string& name, const std::vector<T>& data, size_t rows, size_t cols, const char* units,
               int decimals = -1) {
    requireFinite(name, data, cols, time_s_);
    hsize_t dims[2] = {rows, cols};
    const int rank = cols == 0 ? 1 : 2;
    Handle space(H5Screate_simple(rank, dims, nullptr), H5Sclose, name.c_str());
    // Chunked, shuffled and deflated (HDF5's own filters: lossless but for a float
    // channel's stated resolution). An empty dataset stays contiguous; a channel with a
    // value that is not finite is kept exact (scale-offset cannot hold it).
    Handle dcpl(H5Pcopy(dcpl_), H5Pclose, "dataset creation list");
    bool scaled = false;
    if (compress_ && rows > 0 && (rank == 1 || cols > 0)) {
      const hsize_t chunk[2] = {chunkRows(rows, cols), cols};
      checked(H5Pset_chunk(dcpl, rank, chunk), name + " chunking");
      if constexpr (std::is_floating_point_v<T>) {
        scaled = decimals >= 0 && std::all_of(data.begin(), data.end(), [](T v) { return std::isfinite(v); });
        if (scaled) checked(H5Pset_scaleoffset(dcpl, H5Z_SO_FLOAT_DSCALE, decimals), name + " scale-offset filter");
      }
      checked(H5Pset_shuffle(dcpl), name + " shuffle filter");
      checked(H5Pset_deflate(dcpl, 4), name + " deflate filter");
    }
    Handle ds(H5Dcreate2(file_, name.c_str(), nativeType<T>(), space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose,
              name.c_str());
    if (!data.empty()) checked(H5Dwrite(ds, nativeType<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), name);
    if (units) attr(ds, "units", units);
    // The step result files keep the channel to (an in-memory image holds it exactly).
    if (decimals >= 0) attr(ds, "resolution", std::pow(10.0, -decimals));
  }

  void attr(hid_t obj, const char* name, const std::string& value) {
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
    H5Tset_size(type, value.empty() ? 1 : value.size());
    H5Tset_cset(type, H5T_CSET_UTF8);
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, name);
    Handle a(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, name);
    checked(H5Awrite(a, type, value.empty() ? "" : value.c_str()), name);
  }
  void attr(hid_t obj, const char* name, double value) {
    if (!std::isfinite(value)) {
      std::ostringstream os;
      os << "the attribute " << name << " is " << value << ": a result holds finite numbers only";
      throw NonFiniteValue(os.str());
    }
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, name);
    Handle a(H5Acreate2(obj, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, name);
    checked(H5Awrite(a, H5T_NATIVE_DOUBLE, &value), name);
  }
  void attrInt(hid_t obj, const char* name, long long value) {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, name);
    Handle a(H5Acreate2(obj, name, H5T_NATIVE_LLONG, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, name);
    checked(H5Awrite(a, H5T_NATIVE_LLONG, &value), name);
  }
  void attrOn(const char* path, const char* name, const std::string& value) {
    Handle o(H5Oopen(file_, path, H5P_DEFAULT), H5Oclose, path);
    attr(o, name, value);
  }

  // A vehicle run's lap table: one row per lap started (the last one may be incomplete).
  void laps(const std::vector<LapRecord>& lp) {
    static const char* const kFigures[] = {"start_s", "time_s", "distance_m", "pack_Wh", "array_Wh", "reference_time_s"};
    std::vector<NumberedRow<6>> rows;
    for (const LapRecord& l : lp)
      rows.push_back({l.lap, static_cast<uint8_t>(l.complete ? 1 : 0),
                      {l.start_s, l.time_s, l.distance_m, l.pack_Wh, l.array_Wh, l.reference_time_s}});
    numberedTable("/vehicle/laps", "lap", kFigures, rows);
  }

  // A multi-day route's stage table (route.stages): one row per stage.
  void stages(const std::vector<StageRecord>& st) {
    static const char* const kFigures[] = {"depart_s", "time_s",   "distance_m",     "pack_Wh",
                                           "array_Wh", "parked_s", "parked_pack_Wh", "parked_array_Wh"};
    std::vector<NumberedRow<8>> rows;
    for (const StageRecord& g : st)
      rows.push_back({g.stage, static_cast<uint8_t>(g.complete ? 1 : 0),
                      {g.depart_s, g.time_s, g.distance_m, g.pack_Wh, g.array_Wh, g.parked_s, g.parked_pack_Wh,
                       g.parked_array_Wh}});
    numberedTable("/vehicle/stages", "stage", kFigures, rows);
  }

  void events(const std::vector<Event>& ev) {
    struct Row {
      double time_s;
      const char* kind;
      const char* detail;
    };
    std::vector<Row> rows;
    for (const Event& e : ev) rows.push_back({e.time_s, e.kind.c_str(), e.detail.c_str()});
    const Handle str(newTextType(), H5Tclose, "string type");
    Handle type(H5Tcreate(H5T_COMPOUND, sizeof(Row)), H5Tclose, "events type");
    H5Tinsert(type, "time_s", HOFFSET(Row, time_s), H5T_NATIVE_DOUBLE);
    H5Tinsert(type, "kind", HOFFSET(Row, kind), str);
    H5Tinsert(type, "detail", HOFFSET(Row, detail), str);
    table("/events", type, rows);
  }

  // output.bus_trace: one row per direction of every monitor-bus transaction.
  void busTrace(const std::vector<BusTraceRow>& trace) {
    struct Row {
      double time_s;
      int32_t bus;
      const char* direction;
      int32_t count;
      const char* bytes;
      const char* what;
    };
    std::vector<Row> rows;
    rows.reserve(trace.size());
    for (const BusTraceRow& e : trace)
      rows.push_back({e.time_s, e.bus, e.out ? "out" : "in", e.count, e.bytes.c_str(), e.what.c_str()});
    const Handle str(newTextType(), H5Tclose, "string type");
    Handle type(H5Tcreate(H5T_COMPOUND, sizeof(Row)), H5Tclose, "bus_trace type");
    H5Tinsert(type, "time_s", HOFFSET(Row, time_s), H5T_NATIVE_DOUBLE);
    H5Tinsert(type, "bus", HOFFSET(Row, bus), H5T_NATIVE_INT32);
    H5Tinsert(type, "direction", HOFFSET(Row, direction), str);
    H5Tinsert(type, "count", HOFFSET(Row, count), H5T_NATIVE_INT32);
    H5Tinsert(type, "bytes", HOFFSET(Row, bytes), str);
    H5Tinsert(type, "what", HOFFSET(Row, what), str);
    table("/bus_trace", type, rows);
  }

  // A board alone's CAN bus (hardware.can): every frame, in the order it went on the wire.
  void canTrace(const std::vector<CanTraceRow>& trace) {
    struct Row {
      double time_s, end_s;
      const char* direction;
      int32_t id, dlc;
      const char* data;
      uint8_t lost;
    };
    std::vector<Row> rows;
    rows.reserve(trace.size());
    for (const CanTraceRow& e : trace)
      rows.push_back({e.time_s, e.end_s, e.out ? "out" : "in", e.id, e.dlc, e.data.c_str(), static_cast<uint8_t>(e.lost)});
    const Handle str(newTextType(), H5Tclose, "string type");
    Handle type(H5Tcreate(H5T_COMPOUND, sizeof(Row)), H5Tclose, "can_trace type");
    H5Tinsert(type, "time_s", HOFFSET(Row, time_s), H5T_NATIVE_DOUBLE);
    H5Tinsert(type, "end_s", HOFFSET(Row, end_s), H5T_NATIVE_DOUBLE);
    H5Tinsert(type, "direction", HOFFSET(Row, direction), str);
    H5Tinsert(type, "id", HOFFSET(Row, id), H5T_NATIVE_INT32);
    H5Tinsert(type, "dlc", HOFFSET(Row, dlc), H5T_NATIVE_INT32);
    H5Tinsert(type, "data", HOFFSET(Row, data), str);
    H5Tinsert(type, "lost", HOFFSET(Row, lost), H5T_NATIVE_UINT8);
    table("/can_trace", type, rows);
  }

 private:
  // A row of a vehicle table (laps, stages): its 1-based number, whether it was complete
  // (0: the run ended in it), then N figures.
  template <size_t N>
  struct NumberedRow {
    int32_t number;
    uint8_t complete;
    double figure[N];
  };
  // Such a table at `path`: the number's column named `numberName`, the figures' `figures`;
  // every figure finite.
  template <size_t N>
  void numberedTable(const char* path, const char* numberName, const char* const (&figures)[N],
                     const std::vector<NumberedRow<N>>& rows) {
    for (const NumberedRow<N>& r : rows)
      for (double v : r.figure)
        if (!std::isfinite(v))
          throw NonFiniteValue(std::string(path) + ": " + numberName + " " + std::to_string(r.number) +
                               " holds a non-finite value");
    Handle type(H5Tcreate(H5T_COMPOUND, sizeof(NumberedRow<N>)), H5Tclose, path);
    H5Tinsert(type, numberName, HOFFSET(NumberedRow<N>, number), H5T_NATIVE_INT32);
    H5Tinsert(type, "complete", HOFFSET(NumberedRow<N>, complete), H5T_NATIVE_UINT8);
    for (size_t i = 0; i < N; ++i)
      H5Tinsert(type, figures[i], HOFFSET(NumberedRow<N>, figure) + i * sizeof(double), H5T_NATIVE_DOUBLE);
    table(path, type, rows);
  }

  // A variable-length UTF-8 string: the text fields of the tables below.
  static hid_t newTextType() {
    const hid_t t = H5Tcopy(H5T_C_S1);
    if (t >= 0 && (H5Tset_size(t, H5T_VARIABLE) < 0 || H5Tset_cset(t, H5T_CSET_UTF8) < 0)) {
      H5Tclose(t);
      return -1;
    }
    return t;
  }
  // A one-dimensional table of compound `type` at `path`, compressed like the channels.
  template <typename Row>
  void table(const char* path, hid_t type, const std::vector<Row>& rows) {
    hsize_t dims[1] = {rows.size()};
    Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, path);
    Handle ds(H5Dcreate2(file_, path, type, space, H5P_DEFAULT, dcpl_, H5P_DEFAULT), H5Dclose, path);
    if (!rows.empty()) checked(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data()), path);
  }

  hid_t file_;
  bool compress_;
  const std::vector<double>* time_s_;
  hid_t dcpl_;
  hid_t gcpl_;
};

std::string faultNames() {
  std::string s;
  for (uint8_t i = 0; i < bms::kFaultCount; ++i)
    s += (i ? "," : "") + std::string(bms::faultName(static_cast<bms::FaultId>(i)));
  return s;
}

// /inputs of a batch case: every cell's drawn values and the figures of them.
void writeDrawnInputs(Writer& w, hid_t file, const DrawnInputs& d) {
  w.group("/inputs");
  const size_t cells = d.capacity_Ah.size();
  w.dataset("/inputs/cell_capacity_Ah", d.capacity_Ah, cells, 0, "Ah");
  w.dataset("/inputs/cell_r0_scale", d.r0_scale, cells, 0, "1");
  w.dataset("/inputs/cell_initial_soc", d.initial_soc, cells, 0, "1");
  w.dataset("/inputs/cell_self_discharge_A", d.self_discharge_A, cells, 0, "A");
  Handle g(H5Oopen(file, "/inputs", H5P_DEFAULT), H5Oclose, "inputs");
  for (const auto& [name, value] : drawnInputFigures(d)) {
    if (name == "drawn_weakest_group") w.attrInt(g, name.c_str(), static_cast<long long>(value));
    else w.attr(g, name.c_str(), value);
  }
}

void writeAll(hid_t file, const Scenario& s, const RunResult& r, bool compress, const DrawnInputs* drawn = nullptr) {
  const Recording& rec = r.rec;
  Writer w(file, compress, &rec.time_s);
  const size_t n = rec.samples();
  const size_t cells = static_cast<size_t>(rec.cells);

  w.attr(file, "packsim_version", kVersion);
  w.attr(file, "scenario_name", s.name);
  w.attr(file, "scenario_file", s.file);
  w.attr(file, "scenario_yaml", s.text);
  w.attrInt(file, "seed", static_cast<long long>(s.run.seed));
  w.attr(file, "solver", s.run.solver == RunConfig::Solver::Fast ? "fast" : "cvode");
  w.attr(file, "tick_s", s.bms.tick_s);
  w.attr(file, "sign_convention", "positive current discharges the pack");

  // Every recorded channel (core/sim/result_channels.hpp), each group on first use.
  std::vector<std::string> groups;
  for (const ResultChannel& c : resultChannels()) {
    if (!isRecorded(c, rec)) continue;
    const std::string path = c.path;
    const std::string group = path.substr(0, path.rfind('/'));
    if (!group.empty() && std::find(groups.begin(), groups.end(), group) == groups.end()) {
      w.group(group.c_str());
      groups.push_back(group);
    }
    std::visit([&](const auto& col) { w.dataset(path, rec.*(col.data), n, axisLength(c.axis, rec), c.units, storedDecimals(c)); },
               c.column);
    if (c.attr.name) w.attrOn(c.path, c.attr.name, c.attr.value(rec));
  }
  // Attributes that come from the scenario rather than the recording.
  std::string therm;
  for (const ThermistorChannel& ch : s.hardware.thermistors.channels)  // a series group (1-based), or the node's name
    if (ch.site != ThermSite::Board)
      therm += (therm.empty() ? "" : ",") + (ch.site == ThermSite::Cell ? std::to_string(ch.group + 1) : ch.node);
  w.attrOn("/measured", "thermistor_groups", therm);
  w.attrOn("/bms", "fault_bits", faultNames());
  {  // the protection limits the plots draw (an attribute only when the protection is on)
    Handle bms(H5Oopen(file, "/bms", H5P_DEFAULT), H5Oclose, "/bms");
    const struct {
      const char* name;
      const ProtectionConfig& p;
    } limits[] = {{"limit_cell_overvoltage_V", s.bms.protection(bms::FaultId::CellOverVoltage)},
                  {"limit_cell_undervoltage_V", s.bms.protection(bms::FaultId::CellUnderVoltage)},
                  {"limit_overtemperature_C", s.bms.protection(bms::FaultId::OverTemperature)},
                  {"limit_undertemperature_C", s.bms.protection(bms::FaultId::UnderTemperatureDischarge)},
                  {"limit_overcurrent_discharge_A", s.bms.protection(bms::FaultId::OverCurrentDischarge)},
                  {"limit_overcurrent_charge_A", s.bms.protection(bms::FaultId::OverCurrentCharge)}};
    for (const auto& l : limits)
      if (l.p.enabled) w.attr(bms, l.name, l.p.threshold);
  }
  w.attrOn("/bms/soc_estimate_permille", "estimator", settingChoice("soc.estimator", s.bms.image));
  w.events(r.events);
  if (s.output.bus_trace) w.busTrace(r.bus_trace);
  if (s.hardware.can_alone) w.canTrace(r.can_trace);

  w.group("/summary");
  Handle g(H5Oopen(file, "/summary", H5P_DEFAULT), H5Oclose, "summary");
  const Summary& sm = r.summary;
  // The summary figures (core/sim/summary_fields.hpp), then target mode's own.
  for (const SummaryField& f : summaryFields()) {
    if (f.present && !f.present(sm)) continue;
    std::visit(
        [&](auto read) {
          const auto v = read(sm);
          if constexpr (std::is_same_v<decltype(v), const long long>) w.attrInt(g, f.name, v);
          else w.attr(g, f.name, v);
        },
        f.value);
  }
  for (const auto& [name, value] : sm.firmware_target_figures) w.attr(g, name.c_str(), value);  // target mode only
  if (sm.vehicle.present && !sm.vehicle.laps.empty()) w.laps(sm.vehicle.laps);  // the lap table
  if (sm.vehicle.present && !sm.vehicle.stages.empty()) w.stages(sm.vehicle.stages);  // route.stages: the stage table

  if (drawn) writeDrawnInputs(w, file, *drawn);

  addNetcdfLayout(file, {n, cells, static_cast<size_t>(rec.groups), static_cast<size_t>(rec.thermistors),
                         static_cast<size_t>(rec.devices)});
}

// A new file with the creation and access properties every result file has.
hid_t createFile(const std::string& name, hid_t fapl) {
  H5Pset_libver_bounds(fapl, H5F_LIBVER_V110, H5F_LIBVER_V110);
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "file creation list");
  H5Pset_obj_track_times(fcpl, 0);  // the root group too: same run, same bytes
  return H5Fcreate(name.c_str(), H5F_ACC_TRUNC, fcpl, fapl);
}

// Temporary files of `path` left by a writer that died (killed mid-write: no rename,
// no clean-up): `<path>.tmp.<pid>.<hex>` whose process no longer exists. A live
// writer's file (its pid answers kill(pid, 0)) is never touched.
// (The folder read with readdir: a name that does not start with the prefix costs a
// compare, where std::filesystem's iterator built a path and its filename per entry,
// some 3,000 instructions each, in a folder of a few thousand files.)
void removeStaleTemporaries(const std::filesystem::path& target) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string prefix = target.filename().string() + ".tmp.";
  std::vector<std::string> stale;
  if (DIR* d = ::opendir(dir.c_str())) {
    while (const dirent* e = ::readdir(d)) {
      const char* name = e->d_name;
      if (std::strncmp(name, prefix.c_str(), prefix.size()) != 0) continue;
      char* rest = nullptr;
      const long pid = std::strtol(name + prefix.size(), &rest, 10);
      if (pid <= 0 || !rest || *rest != '.') continue;
      if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) stale.emplace_back(name);
    }
    ::closedir(d);
  }
  for (const std::string& name : stale) fs::remove(dir / name, ec);  // after the listing, not during it
}

}  // namespace

void writeResultHdf5(const std::string& path, const Scenario& s, const RunResult& r, const DrawnInputs* drawn) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  if (target.has_parent_path()) fs::create_directories(target.parent_path());
  removeStaleTemporaries(target);
  const std::string tmp = uniqueTemporaryName(path);  // this process's own: concurrent writers never share it
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become exceptions, not stderr dumps
  try {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access list");
    Handle file(createFile(tmp, fapl), H5Fclose, tmp.c_str());
    writeAll(file, s, r, true, drawn);
    file.close(tmp.c_str());
    if (const int sig = stopSignal())
      throw Interrupted(sig, "interrupted by " + stopSignalName(sig) + " while writing " + path + "; nothing written");
  } catch (const Interrupted&) {
    std::remove(tmp.c_str());
    throw;
  } catch (const NonFiniteValue& e) {
    std::remove(tmp.c_str());
    throw std::runtime_error("the run's result is not written to '" + path + "': " + e.what());
  } catch (const std::exception& e) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write the result file '" + path + "': " + e.what() +
                             (err ? std::string(" (") + std::strerror(err) + ")" : std::string()));
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);  // atomic: readers see the old file or the complete new one
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write the result file '" + path + "': renaming the complete temporary file '" + tmp +
                             "' failed: " + ec.message());
  }
}

std::string uniqueTemporaryName(const std::string& path) {
  std::random_device rd;
  char suffix[48];
  std::snprintf(suffix, sizeof suffix, ".tmp.%ld.%08x", static_cast<long>(getpid()), static_cast<unsigned>(rd()));
  return path + suffix;
}

ResultFileStamp resultFileStamp(const std::string& path) {
  ResultFileStamp st;
  struct stat sb;
  if (::stat(path.c_str(), &sb) != 0) return st;
  st.exists = true;
  st.device = static_cast<unsigned long long>(sb.st_dev);
  st.inode = static_cast<unsigned long long>(sb.st_ino);
  st.size = static_cast<long long>(sb.st_size);
  st.mtime_ns = static_cast<long long>(sb.st_mtim.tv_sec) * 1000000000LL + sb.st_mtim.tv_nsec;
  return st;
}

void checkResultPathWritable(const std::string& path) {
  namespace fs = std::filesystem;
  auto fail = [&](const std::string& why) {
    throw std::invalid_argument("cannot write the result file '" + path + "': " + why);
  };
  const fs::path target(path);
  std::error_code ec;
  const fs::file_status st = fs::status(target, ec);
  if (fs::exists(st) && !fs::is_regular_file(st)) fail(fs::is_directory(st) ? "it is a folder" : "it is not a regular file");
  if (target.has_parent_path()) {
    fs::create_directories(target.parent_path(), ec);
    if (ec) fail("cannot create the folder '" + target.parent_path().string() + "': " + ec.message());
  }
  const std::string probe = uniqueTemporaryName(path);
  errno = 0;
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (!f) fail(std::strerror(errno));
  std::fclose(f);
  std::remove(probe.c_str());
}

namespace {

// HDF5's in-memory (core) driver with our own memory callbacks: the driver hands its
// buffer to imageFree when the file closes, complete and consistent. (Not
// H5Fget_file_image on the open file: HDF5 1.10 clears the superblock's open-for-write
// flag in that copy without updating its checksum, and the image does not open.)
struct ImageCapture {
  size_t allocated = 0;
  std::string image;
};
void* imageMalloc(size_t n, H5FD_file_image_op_t, void* u) {
  static_cast<ImageCapture*>(u)->allocated = n;
  return std::calloc(n, 1);
}
void* imageMemcpy(void* dst, const void* src, size_t n, H5FD_file_image_op_t, void*) { return std::memcpy(dst, src, n); }
void* imageRealloc(void* p, size_t n, H5FD_file_image_op_t, void* u) {
  auto* c = static_cast<ImageCapture*>(u);
  void* q = std::realloc(p, n);
  if (q && n > c->allocated) std::memset(static_cast<char*>(q) + c->allocated, 0, n - c->allocated);
  if (q) c->allocated = n;
  return q;
}
herr_t imageFree(void* p, H5FD_file_image_op_t op, void* u) {
  auto* c = static_cast<ImageCapture*>(u);
  if (op == H5FD_FILE_IMAGE_OP_FILE_CLOSE && p) c->image.assign(static_cast<const char*>(p), c->allocated);
  std::free(p);
  return 0;
}
void* imageUdataCopy(void* u) { return u; }
herr_t imageUdataFree(void*) { return 0; }

}  // namespace

std::string resultHdf5Image(const Scenario& s, const RunResult& r) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  ImageCapture capture;
  hsize_t size = 0;
  {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access list");
    checked(H5Pset_fapl_core(fapl, 1 << 20, 0), "in-memory file driver");  // never touches the disk
    H5FD_file_image_callbacks_t callbacks = {imageMalloc,    imageMemcpy,    imageRealloc, imageFree,
                                             imageUdataCopy, imageUdataFree, &capture};
    checked(H5Pset_file_image_callbacks(fapl, &callbacks), "in-memory file callbacks");
    Handle file(createFile("packsim-result-in-memory.h5", fapl), H5Fclose, "in-memory result file");
    writeAll(file, s, r, false);
    checked(H5Fflush(file, H5F_SCOPE_GLOBAL), "in-memory result file");
    checked(H5Fget_filesize(file, &size), "in-memory result file size");
  }  // closed: the driver hands its buffer to imageFree
  if (capture.image.size() < size) throw std::runtime_error("HDF5: the in-memory result file is incomplete");
  capture.image.resize(static_cast<size_t>(size));
  return capture.image;
}

}  // namespace packsim

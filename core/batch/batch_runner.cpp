#include "core/batch/batch_runner.hpp"

#include "core/sim/firmware_failure.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include "core/batch/case_inputs.hpp"
#include "core/batch/case_processes.hpp"
#include "core/batch/drawn_inputs.hpp"
#include "core/io/hdf5_writer.hpp"
#include "core/scenario/overrides.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/stop_signal.hpp"
#include "core/sim/summary_fields.hpp"
#include "core/sim/summary_text.hpp"

namespace packsim {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// HDF5 is built thread-safe on Debian, but one lock keeps this correct on builds that
// are not; file I/O is a small part of a case.
std::mutex& hdf5Mutex() {
  static std::mutex m;
  return m;
}

std::string readStringAttr(hid_t attr) {
  const hid_t type = H5Aget_type(attr);
  std::string out;
  if (H5Tis_variable_str(type) > 0) {
    char* s = nullptr;
    const hid_t mem = H5Tget_native_type(type, H5T_DIR_ASCEND);
    if (H5Aread(attr, mem, &s) >= 0 && s) {
      out = s;
      H5free_memory(s);
    }
    H5Tclose(mem);
  } else {
    const size_t n = H5Tget_size(type);
    std::string buf(n, '\0');
    if (n > 0 && H5Aread(attr, type, buf.data()) >= 0) out = buf.substr(0, buf.find('\0'));
  }
  H5Tclose(type);
  return out;
}

std::string attrText(hid_t attr) {
  const hid_t type = H5Aget_type(attr);
  const H5T_class_t cls = H5Tget_class(type);
  H5Tclose(type);
  char buf[64];
  if (cls == H5T_FLOAT) {
    double v = 0.0;
    H5Aread(attr, H5T_NATIVE_DOUBLE, &v);
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
  }
  if (cls == H5T_INTEGER) {
    long long v = 0;
    H5Aread(attr, H5T_NATIVE_LLONG, &v);
    std::snprintf(buf, sizeof buf, "%lld", v);
    return buf;
  }
  if (cls == H5T_STRING) return readStringAttr(attr);
  return "";
}

herr_t collect(hid_t loc, const char* name, const H5A_info_t*, void* data) {
  auto* out = static_cast<std::vector<std::pair<std::string, std::string>>*>(data);
  const hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  if (a < 0) return 0;
  out->emplace_back(name, attrText(a));
  H5Aclose(a);
  return 0;
}

std::string firstLine(const std::string& s) { return s.substr(0, s.find('\n')); }

// Progress on a terminal: one bar rewritten in place; otherwise a line per case.
class Progress {
 public:
  Progress(std::FILE* out, int total) : out_(out), total_(total), start_(Clock::now()) {
    tty_ = out_ && isatty(fileno(out_));
  }
  void caseDone(const SweepCase& c, const CaseOutcome& o) {
    std::lock_guard<std::mutex> lock(m_);
    ++done_;
    if (!o.skipped) ++ran_;
    if (!o.ok) ++failed_;
    if (!out_) return;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    if (tty_) {
      constexpr int kWidth = 30;
      const int filled = total_ ? kWidth * done_ / total_ : kWidth;
      std::string bar(static_cast<size_t>(filled), '#');
      bar.resize(kWidth, '-');
      std::string eta = "--:--:--";
      if (ran_ > 0 && done_ < total_) eta = clockText(elapsed / ran_ * (total_ - done_));
      std::fprintf(out_, "\r[%s] %d/%d %3d%%  %d failed  elapsed %s  ETA %s ", bar.c_str(), done_, total_,
                   total_ ? 100 * done_ / total_ : 100, failed_, clockText(elapsed).c_str(), eta.c_str());
      if (done_ == total_) std::fprintf(out_, "\n");
    } else {
      const int w = static_cast<int>(std::to_string(total_).size());
      if (o.skipped)
        std::fprintf(out_, "[%*d/%d] case_%s skipped (complete result)\n", w, done_, total_, c.id.c_str());
      else if (o.ok)
        std::fprintf(out_, "[%*d/%d] case_%s ok %.2f s\n", w, done_, total_, c.id.c_str(), o.wall_s);
      else
        std::fprintf(out_, "[%*d/%d] case_%s FAILED: %s\n", w, done_, total_, c.id.c_str(), firstLine(o.error).c_str());
    }
    std::fflush(out_);
  }

 private:
  std::mutex m_;
  std::FILE* out_;
  bool tty_ = false;
  int total_;
  int done_ = 0, ran_ = 0, failed_ = 0;
  Clock::time_point start_;
};

}  // namespace

CaseOutcome runSweepCase(const Sweep& sw, const SweepCase& c, bool resume) {
  CaseOutcome o;
  const std::string path = sw.resultPath(c);
  const std::string errFile = sw.base_path + " (sweep " + sw.name + ", case " + c.id + ")";
  try {
    const std::string dir = fs::path(sw.base_path).parent_path().string();
    const Scenario s = loadScenarioWithOverrides(sw.base_text, c.params, errFile, dir.empty() ? "." : dir);
    if (resume && fs::exists(path)) {
      std::string stored;
      auto summary = readResultSummary(path, &stored);
      // Complete, this very scenario -- the text the run stores, a base's extends: chain
      // merged in (the base's own text never matched that, so such a batch never resumed)
      // -- written after every file the case reads changed (an edited load CSV ran
      // again, core/batch/case_inputs.hpp), and its drawn inputs recorded (a file of an
      // older packsim without /inputs runs again, so summary.csv has them for every case).
      const bool drawn = std::any_of(summary.begin(), summary.end(),
                                     [](const auto& kv) { return kv.first.rfind("drawn_", 0) == 0; });
      if (!summary.empty() && stored == s.text && drawn && newerThanInputs(path, caseInputFiles(sw, s))) {
        o.ok = o.skipped = true;
        o.summary = std::move(summary);
        return o;
      }
    }
    const auto t0 = Clock::now();
    // A stop signal (packsim batch only, core/sim/stop_signal.hpp) ends the case at the next tick, unwritten.
    const RunResult r =
        runScenario(s, [](double, const double*, const PlantSignals&, const bms::Outputs&) { return stopSignal() != 0; });
    if (const int sig = stopSignal()) throw Interrupted(sig, "interrupted by " + stopSignalName(sig));
    // A firmware that failed is a failed case, as `packsim run` exits 1 for it; no file, so
    // a resumed batch runs the case again rather than taking it as done.
    if (const std::string fw = s.expect.firmware_fault ? std::string() : firmwareFailure(s, r); !fw.empty())
      throw std::runtime_error(fw);
    {
      std::lock_guard<std::mutex> lock(hdf5Mutex());
      const DrawnInputs drawn = drawnInputs(s);
      writeResultHdf5(path, s, r, &drawn);
    }
    o.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    o.summary = readResultSummary(path, nullptr);
    o.ok = true;
  } catch (const std::exception& e) {
    o.ok = false;
    o.error = e.what();
  } catch (...) {
    o.ok = false;
    o.error = "unknown error";
  }
  return o;
}

void writeSummaryCsv(const Sweep& sw, const BatchReport& rep) {
  // The union of the summary attributes: the drawn inputs (core/batch/drawn_inputs.hpp)
  // in their order, the summary table's leading columns (core/sim/summary_fields.hpp),
  // then any others alphabetically.
  std::vector<std::string> seen;
  for (const CaseOutcome& o : rep.cases)
    for (const auto& kv : o.summary)
      if (std::find(seen.begin(), seen.end(), kv.first) == seen.end()) seen.push_back(kv.first);
  std::vector<std::string> fields;
  for (const std::string& k : drawnInputNames())
    if (std::find(seen.begin(), seen.end(), k) != seen.end()) fields.push_back(k);
  for (const std::string& k : summaryCsvLeadingColumns())
    if (std::find(seen.begin(), seen.end(), k) != seen.end()) fields.push_back(k);
  std::vector<std::string> rest;
  for (const std::string& k : seen)
    if (std::find(fields.begin(), fields.end(), k) == fields.end()) rest.push_back(k);
  std::sort(rest.begin(), rest.end());
  fields.insert(fields.end(), rest.begin(), rest.end());
  const std::string tmp = uniqueTemporaryName(rep.csv_path);  // two batches into one folder never share it
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw std::runtime_error("cannot write " + tmp);
    out << "case";
    for (const std::string& k : sw.keys) out << ',' << csvField(k);
    out << ",status";
    for (const std::string& f : fields) out << ',' << csvField(f);
    out << ",error,file\n";
    for (size_t i = 0; i < sw.cases.size(); ++i) {
      const SweepCase& c = sw.cases[i];
      const CaseOutcome& o = rep.cases[i];
      out << c.id;
      for (const std::string& k : sw.keys) {
        std::string v;
        for (const auto& kv : c.params)
          if (kv.first == k) v = kv.second;
        out << ',' << csvField(v);
      }
      out << ',' << (o.ok ? "ok" : "failed");
      for (const std::string& f : fields) {
        std::string v;
        for (const auto& kv : o.summary)
          if (kv.first == f) v = kv.second;
        out << ',' << csvField(v);
      }
      out << ',' << csvField(o.error) << ',' << csvField(o.ok ? fs::path(sw.resultPath(c)).filename().string() : "")
          << '\n';
    }
  }
  std::error_code ec;
  fs::rename(tmp, rep.csv_path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write " + rep.csv_path + ": " + ec.message());
  }
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) {
    if (ch == '"') q += '"';
    q += ch;
  }
  return q + "\"";
}

std::vector<std::pair<std::string, std::string>> readResultSummary(const std::string& path, std::string* scenario_yaml) {
  std::vector<std::pair<std::string, std::string>> out;
  std::lock_guard<std::mutex> lock(hdf5Mutex());
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return out;
  if (scenario_yaml && H5Aexists(f, "scenario_yaml") > 0) {
    const hid_t a = H5Aopen(f, "scenario_yaml", H5P_DEFAULT);
    *scenario_yaml = readStringAttr(a);
    H5Aclose(a);
  }
  // The drawn inputs of a batch case first (core/batch/drawn_inputs.hpp), then the run's summary.
  for (const char* group : {"/inputs", "/summary"}) {
    if (H5Lexists(f, group, H5P_DEFAULT) <= 0) continue;
    const hid_t g = H5Oopen(f, group, H5P_DEFAULT);
    if (g < 0) continue;
    hsize_t idx = 0;
    H5Aiterate2(g, H5_INDEX_NAME, H5_ITER_NATIVE, &idx, collect, &out);
    H5Oclose(g);
  }
  H5Fclose(f);
  return out;
}

BatchReport runBatch(const Sweep& sw, const BatchOptions& opt) {
  BatchReport rep;
  rep.total = static_cast<int>(sw.cases.size());
  rep.cases.resize(sw.cases.size());
  rep.csv_path = sw.summaryCsvPath();
  int threads = opt.threads > 0 ? opt.threads : sw.threads;
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::max(1, std::min(threads, rep.total));
  rep.threads = threads;
  fs::create_directories(sw.output_dir);

  const auto t0 = Clock::now();
  Progress progress(opt.progress, rep.total);
  if (opt.isolate) {
    runCasesInProcesses(sw, opt.resume, threads, rep.cases, [&](size_t i) {
      if (rep.cases[i].ok) rep.cases[i].summary = readResultSummary(sw.resultPath(sw.cases[i]), nullptr);
      progress.caseDone(sw.cases[i], rep.cases[i]);
    });
  }
  std::atomic<size_t> next{opt.isolate ? sw.cases.size() : 0};
  auto worker = [&]() {
    for (size_t i = next++; i < sw.cases.size(); i = next++) {
      rep.cases[i] = runSweepCase(sw, sw.cases[i], opt.resume);
      progress.caseDone(sw.cases[i], rep.cases[i]);
    }
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < threads && !opt.isolate; ++k) pool.emplace_back(worker);
  worker();  // the calling thread is one of the workers
  for (std::thread& t : pool) t.join();
  rep.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();

  for (size_t i = 0; i < rep.cases.size(); ++i) {
    CaseOutcome& o = rep.cases[i];
    if (!o.ok && o.error.empty() && stopSignal()) o.error = "not run (interrupted by " + stopSignalName(stopSignal()) + ")";
    if (!o.ok && o.error.empty()) o.error = "not run";
    if (o.ok) ++rep.ok;
    else ++rep.failed;
    if (o.skipped) ++rep.skipped;
  }
  writeSummaryCsv(sw, rep);
  return rep;
}

}  // namespace packsim

// output.bus_trace: every monitor-bus transaction as the MCU sees it, against the
// bytes the data sheets give and the truth at the pins; and a trace changes nothing
// the run does.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario bundled(const std::string& file, double duration_s, bool trace) {
  return test::scenarioFromYaml("extends: " + file + "\nrun: {duration_s: " + std::to_string(duration_s) +
                                "}\noutput: {interval_s: 0.1, bus_trace: " + (trace ? "true" : "false") + "}\n");
}

int hexByte(const std::string& bytes, size_t i) { return std::stoi(bytes.substr(3 * i, 2), nullptr, 16); }

// The BQ76952 (I2C at 0x08, CRC on): the driver's read of Cell 1 Voltage is the
// address byte 0x10 and command 0x14; the reply's first data byte and the byte after
// its CRC are the cell's mV, little-endian, within the part's ±5 mV of the truth.
TEST(BusTrace, Bq76952CellReadsAreTheDataSheetsBytesAndTheTruth) {
  const Scenario off = bundled("scooter_16s_lto.yaml", 11.0, false);
  const Scenario on = bundled("scooter_16s_lto.yaml", 11.0, true);
  ASSERT_TRUE(on.hardware.afe.crc);
  const RunResult a = runScenario(off), b = runScenario(on);
  EXPECT_TRUE(a.bus_trace.empty());
  // The trace changes nothing: the recording, the events and the summary are the same.
  EXPECT_EQ(a.rec.cell_voltage_V, b.rec.cell_voltage_V);
  EXPECT_EQ(a.rec.meas_cell_voltage_mV, b.rec.meas_cell_voltage_mV);
  ASSERT_EQ(a.events.size(), b.events.size());
  for (size_t i = 0; i < a.events.size(); ++i) EXPECT_EQ(a.events[i].detail, b.events[i].detail);
  EXPECT_EQ(formatSummary(off, a), formatSummary(on, b));

  ASSERT_FALSE(b.bus_trace.empty());
  int cellReads = 0;
  for (size_t i = 0; i + 1 < b.bus_trace.size(); ++i) {
    const BusTraceRow& out = b.bus_trace[i];
    EXPECT_EQ(out.bus, 0);
    if (i > 0) EXPECT_GE(out.time_s, b.bus_trace[i - 1].time_s - 1e-12);
    if (!out.out || out.bytes != "10 14") continue;
    EXPECT_EQ(out.what, "read Cell 1 Voltage");
    const BusTraceRow& in = b.bus_trace[i + 1];
    ASSERT_FALSE(in.out);
    EXPECT_EQ(in.what, "read Cell 1 Voltage");
    ASSERT_GE(in.count, 4);
    EXPECT_GT(in.time_s, out.time_s);
    const int mV = hexByte(in.bytes, 0) | (hexByte(in.bytes, 2) << 8);
    const size_t k = test::sampleAt(b.rec, std::floor(out.time_s * 10.0 + 1e-9) / 10.0);
    EXPECT_NEAR(mV, 1e3 * b.rec.cell_voltage_V[k * static_cast<size_t>(b.rec.cells)], 10.0) << out.time_s;
    ++cellReads;
  }
  EXPECT_EQ(cellReads, 3);  // its read-out every 5 s: at 0, 5 and 10 s
}

// Several boards: each board's host on its own bus; the BQ76PL536A's frames decoded.
TEST(BusTrace, EveryBoardsBusIsTracedAndDecoded) {
  const Scenario s = bundled("motorcycle_110s.yaml", 0.5, true);
  const RunResult r = runScenario(s);
  std::set<int> buses;
  bool cellRead = false;
  for (const BusTraceRow& row : r.bus_trace) {
    buses.insert(row.bus);
    EXPECT_FALSE(row.what.empty());
    // A read request: address << 1, register, count: the driver's block read from
    // DEVICE_STATUS (0x00) through the cells and temperatures (19 bytes).
    if (row.out && row.count == 3 && hexByte(row.bytes, 1) == 0x00 && hexByte(row.bytes, 2) == 19) {
      cellRead = true;
      EXPECT_EQ(row.what.rfind("read DEVICE_STATUS +18", 0), 0u) << row.what;
      EXPECT_NE(row.what.find("at address " + std::to_string(hexByte(row.bytes, 0) >> 1)), std::string::npos) << row.what;
    }
  }
  EXPECT_TRUE(cellRead);
  EXPECT_EQ(static_cast<int>(buses.size()), (s.hardware.afe.devices + s.hardware.afe.devices_per_board - 1) / s.hardware.afe.devices_per_board);
}

// The LTC6813: conversions and reads by their data-sheet names.
TEST(BusTrace, Ltc6813CommandsByTheirNames) {
  const RunResult r = runScenario(bundled("formula_student_96s.yaml", 0.5, true));
  bool adcv = false, rdcva = false;
  for (const BusTraceRow& row : r.bus_trace) {
    if (!row.out) continue;
    adcv = adcv || row.what.rfind("ADCV ", 0) == 0;
    if (row.what == "RDCVA") {
      rdcva = true;
      EXPECT_EQ(row.bytes.substr(0, 5), "00 04");  // CMD0 CMD1 of RDCVA
    }
  }
  EXPECT_TRUE(adcv);
  EXPECT_TRUE(rdcva);
}

}  // namespace
}  // namespace packsim

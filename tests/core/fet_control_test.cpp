// hardware.fet_control: who switches the FET gates, and the summary line for a FET that
// never conducted although the firmware asked for it (core/sim/hw_fet_watch.hpp).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/overrides.hpp"
#include "core/sim/bms_bridge.hpp"
#include "core/sim/simulation.hpp"
#include "models/random/random.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::string board(const std::string& afe, const std::string& extra = "") {
  return "name: fets\npack:\n  series: 12\n  cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}\n"
         "hardware:\n  afe: " + afe + "\n" + extra + "load: {current_A: 2}\nrun: {duration_s: 1}\n";
}

// The FET hardware alone, with no firmware: the MCU's pins held as given for n ticks.
struct Board {
  explicit Board(const Scenario& sc) : s(sc), plant(s), hw(s, plant), rng(1), sig(plant.makeSignals()) {
    inputs.faults = &faults;
    inputs.load = s.load.segmentAt(0.0);
    x.assign(static_cast<size_t>(plant.stateSize()), 0.0);
    plant.initialState(x.data());
  }
  void run(bool dsgPin, bool chgPin, int ticks) {
    bms::Outputs out{};
    out.dischargeFetOn = dsgPin;
    out.chargeFetOn = chgPin;
    for (int k = 0; k < ticks; ++k, ++tick) {
      const double t = tick * s.bms.tick_s;
      plant.evaluate(t, x.data(), inputs, sig);
      hw.sample(t, sig, sig, faults, rng, in);  // no balancing: the unloaded view is sig
      hw.actuate(t, out, sig, faults, inputs);
    }
  }
  double now_s() const { return tick * s.bms.tick_s; }
  Scenario s;
  Plant plant;
  HardwareSim hw;
  Rng rng;
  HardwareFaults faults;
  PlantInputs inputs;
  PlantSignals sig;
  std::vector<double> x;
  bms::Inputs in{};
  int tick = 0;
};

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const std::string& s : v) out += s + "\n";
  return out;
}

// The default follows the part: a BQ76952 drives its gates itself; other parts leave them
// to the MCU and refuse the other wirings, naming the key and what is allowed.
TEST(FetControl, DefaultFollowsThePartAndOthersRefuseIt) {
  EXPECT_EQ(test::scenarioFromYaml(board("{model: bq76952}")).hardware.fet_control, FetControl::Afe);
  EXPECT_EQ(test::scenarioFromYaml(board("{model: bq76pl536a, cells_per_device: 6}")).hardware.fet_control,
            FetControl::Mcu);
  EXPECT_EQ(test::scenarioFromYaml(board("{model: bq76952}", "  fet_control: afe_and_mcu\n")).hardware.fet_control,
            FetControl::AfeAndMcu);
  const std::string e =
      test::yamlErrorOf(board("{model: bq76pl536a, cells_per_device: 6}", "  fet_control: afe_and_mcu\n"));
  EXPECT_NE(e.find("hardware.fet_control"), std::string::npos) << e;
  EXPECT_NE(e.find("needs a monitor part that drives FETs of its own (bq76952; this board's is a bq76pl536a)"),
            std::string::npos) << e;
  EXPECT_NE(e.find("allowed here: mcu"), std::string::npos) << e;
  const std::string typo = test::yamlErrorOf(board("{model: bq76952}", "  fet_control: both\n"));
  EXPECT_NE(typo.find("afe_and_mcu"), std::string::npos) << typo;
}

// A BQ76952 powers up in FET test mode: its drivers stay off until the host sends
// FET_ENABLE. With no firmware to send it, the MCU's pins alone get the FETs on only on
// a board where the pins drive the gates (mcu); on the board as built (afe) and with the
// pins on DFETOFF/CFETOFF (afe_and_mcu) nothing conducts, and the summary line says why.
TEST(FetControl, PinsWithoutTheDriverGiveTheReasonLine) {
  for (const char* control : {"afe", "afe_and_mcu", "mcu"}) {
    Board b(test::scenarioFromYaml(board("{model: bq76952}", std::string("  fet_control: ") + control + "\n")));
    b.run(true, true, 20);
    const std::vector<std::string> notes = b.hw.fetNotes(b.now_s());
    const std::string text = joined(notes);
    if (std::string(control) == "mcu") {
      EXPECT_FALSE(b.inputs.discharge_blocked) << control;
      EXPECT_TRUE(b.hw.status().discharge_fet_on) << control;
      EXPECT_TRUE(notes.empty()) << text;
      continue;
    }
    EXPECT_TRUE(b.inputs.discharge_blocked) << control;
    EXPECT_FALSE(b.hw.status().discharge_fet_on) << control;
    ASSERT_EQ(notes.size(), 1u) << text;  // no charge FET on this board
    const std::string on = "on for " + std::to_string(20 * b.s.bms.tick_s).substr(0, 3) + " s";
    EXPECT_NE(text.find("discharge FET off all run: the bq76952's DSG driver never on (FET_EN clear: FET test mode"),
              std::string::npos) << text;
    EXPECT_NE(text.find("the MCU's discharge FET pin was " + on), std::string::npos) << text;
    EXPECT_NE(text.find(std::string("hardware.fet_control: ") + control + " --"), std::string::npos) << text;
  }
}

// Nobody asked (pins low, driver in FET test mode): no line; a FET that conducted at
// some time: no line either.
TEST(FetControl, NoLineWhenNotAskedOrConducting) {
  Board quiet(test::scenarioFromYaml(board("{model: bq76952}", "  fet_control: afe_and_mcu\n")));
  quiet.run(false, false, 10);
  EXPECT_TRUE(quiet.hw.fetNotes(quiet.now_s()).empty());
  Board once(test::scenarioFromYaml(board("{model: bq76pl536a, cells_per_device: 6}")));
  once.run(true, true, 3);
  once.run(false, false, 10);
  EXPECT_TRUE(once.hw.fetNotes(once.now_s()).empty());
}

// The watch alone: the driver on while the pin held DFETOFF all run, with the times
// the levels were held.
TEST(FetControl, WatchNamesThePinThatHeldTheGateOff) {
  FetWatch w;
  SwitchDrive d;
  d.dischargePin = false;
  d.afeDischarge = false;
  SwitchState off;
  w.hold(0.0, d, off, "", "");
  d.afeDischarge = true;
  w.hold(1.0, d, off, "", "");  // the part's driver on from 1 s, the pin still low
  const std::vector<std::string> n = w.notes(3.5, FetControl::AfeAndMcu, "bq76952", false);
  ASSERT_EQ(n.size(), 1u);
  EXPECT_EQ(n[0],
            "discharge FET off all run: the MCU's discharge FET pin never on while the bq76952's DSG driver was on "
            "for 2.5 s; hardware.fet_control: afe_and_mcu -- the pin holds the gate off (DFETOFF)");
  EXPECT_TRUE(w.notes(3.5, FetControl::Afe, "bq76952", false).empty());  // the gate was the driver: not asked by pin
}

// A FET whose gate was on once is settled: what its pin and driver do later gives no
// line (and is not kept); the other FET is still watched, its times as held.
TEST(FetControl, WatchSettlesAFetOnceItsGateWasOn) {
  FetWatch w;
  SwitchDrive d;
  SwitchState s;
  d.dischargePin = d.afeDischarge = true;
  s.dsg = true;  // the discharge gate on at 0 s
  d.chargePin = true;  // the charge pin on, its driver off, all run
  d.afeCharge = false;
  w.hold(0.0, d, s, "", "CHG held off");
  EXPECT_FALSE(w.settled());
  d.afeDischarge = false;  // the discharge driver off from 1 s with the pin on: settled, no line
  s.dsg = false;
  w.hold(1.0, d, s, "DSG held off", "CHG held off");
  w.hold(2.25, d, s, "DSG held off", "CHG held off");
  const std::vector<std::string> n = w.notes(4.0, FetControl::AfeAndMcu, "bq76952", true);
  ASSERT_EQ(n.size(), 1u);
  EXPECT_EQ(n[0],
            "charge FET off all run: the bq76952's CHG driver never on (CHG held off) while the MCU's charge FET pin "
            "was on for 4.0 s; hardware.fet_control: afe_and_mcu -- both must be on");
  s.chg = true;  // the charge gate on too: both settled, no line at all
  w.hold(5.0, d, s, "", "");
  EXPECT_TRUE(w.settled());
  EXPECT_TRUE(w.notes(6.0, FetControl::AfeAndMcu, "bq76952", true).empty());
}

// packsim's core drives the FETs both ways (pins and bus), so the bundled BQ76952 pack
// delivers energy on each wiring, with no FETs line.
TEST(FetControl, CoreRunsOnEveryWiring) {
  for (const char* control : {"afe", "afe_and_mcu", "mcu"}) {
    const Scenario s = loadScenarioFileWithOverrides(test::scenarioDir() + "/scooter_16s_lto.yaml",
                                                     {{"hardware.fet_control", control}, {"run.duration_s", "20"}});
    const RunResult r = runScenario(s);
    EXPECT_GT(r.summary.energy_delivered_Wh, 1.0) << control;
    EXPECT_TRUE(r.summary.fet_notes.empty()) << control << ": " << joined(r.summary.fet_notes);
  }
}

}  // namespace
}  // namespace packsim

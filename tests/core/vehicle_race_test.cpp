// The bundled races (scenarios/vehicle) against hand energy budgets, and the pack's
// limits acting back on the vehicle (docs/vehicle.md). Each hand figure below is
// worked from the scenario's own numbers with the road-load equation written out
// again here, not with models/vehicle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "core/scenario/overrides.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

using namespace packsim;

namespace {

constexpr double kG = 9.80665;

std::string race(const std::string& name) { return test::scenarioDir() + "/vehicle/" + name + ".yaml"; }

// Steady wheel force on grade G (rise/run) at v: m·g·(C_rr·cos θ + sin θ) + ½·ρ·CdA·v².
double force_N(double m, double crr, double rho, double cda, double v, double grade) {
  const double c = 1.0 / std::sqrt(1.0 + grade * grade);
  return m * kG * (crr * c + grade * c) + 0.5 * rho * cda * v * v;
}

// Eco circuit (eco_marathon_12s_circuit.yaml): 220 kg, C_rr 0.006, CdA 0.25, ρ 1.2, η 0.85,
// aux 8 W; 600 m flat, 250 m at +3 %, 250 m at -3 % (no regeneration: the drive gives
// nothing, the brakes hold the speed), 500 m flat; 27 km/h.
constexpr double kEcoV = 27.0 / 3.6;
double ecoLapWheel_J() {
  const double flat = force_N(220, 0.006, 1.2, 0.25, kEcoV, 0.0);
  const double up = force_N(220, 0.006, 1.2, 0.25, kEcoV, 0.03);
  EXPECT_LT(force_N(220, 0.006, 1.2, 0.25, kEcoV, -0.03), 0.0);  // downhill the car brakes
  return flat * 1100.0 + up * 250.0;
}
double ecoLapPack_J() { return ecoLapWheel_J() / 0.85 + 8.0 * 1600.0 / kEcoV; }

}  // namespace

TEST(VehicleRace, EcoCircuitLapEnergyIsTheHandRoadLoadBudget) {
  const Scenario s = loadScenarioFile(race("eco_marathon_12s_circuit"));
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.present);
  ASSERT_TRUE(v.finished);
  ASSERT_EQ(v.laps.size(), 10u);
  // Per lap at cruise: 15.19 Wh (flat 21.38 N over 1100 m, the climb 86.07 N over 250 m).
  const double lap_Wh = ecoLapPack_J() / 3600.0;
  EXPECT_NEAR(lap_Wh, 15.19, 0.01);
  for (size_t i = 1; i < v.laps.size(); ++i) {
    EXPECT_NEAR(v.laps[i].pack_Wh, lap_Wh, 0.02 * lap_Wh) << "lap " << i + 1;
    EXPECT_NEAR(v.laps[i].time_s, 1600.0 / kEcoV, 0.05) << "lap " << i + 1;
  }
  // The race: ten laps plus the start, ½·m·v²/η, from the pack (its energy quadrature).
  const double race_Wh = (10.0 * ecoLapPack_J() + 0.5 * 220.0 * kEcoV * kEcoV / 0.85) / 3600.0;
  EXPECT_NEAR(r.summary.energy_delivered_Wh, race_Wh, 0.02 * race_Wh);
  EXPECT_NEAR(v.pack_Wh, r.summary.energy_delivered_Wh, 1e-9);
  // Its time limit: 2400 s for 16 km at 27 km/h (2133 s a lap of cruise, plus the start).
  EXPECT_LT(v.time_s - v.start_s, 2400.0);
  const std::string text = formatSummary(s, r);
  EXPECT_NE(text.find("time limit      2400 s: met with"), std::string::npos) << text;
  // Nothing limited it: no vehicle_limited event, and the reference car is no faster.
  EXPECT_FALSE(v.limited);
  EXPECT_LT(test::eventTime(r, "vehicle_limited"), 0.0);
  EXPECT_NEAR(v.time_s, v.reference_time_s, 1e-9);
  EXPECT_NE(text.find("pack limit      none"), std::string::npos);
}

TEST(VehicleRace, ControllerCurrentLimitSlowsTheClimbAndTheLostTimeAddsUp) {
  // At 12 A the climb's 759 W (17 A at 44 V) is cut back: the car slows on the hill (and
  // already at the start: 0.5 m/s² needs 570 W at 14 km/h).
  // (The fast integrator: a power that changes every tick restarts CVODE every tick.)
  const Scenario s = loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"),
                                                   {{"load.vehicle.max_current_A", "12"}, {"run.solver", "fast"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  ASSERT_TRUE(v.limited);
  EXPECT_EQ(v.limit_lap, 1);
  EXPECT_LT(v.limit_distance_m, 600.0);  // accelerating on the first flat
  EXPECT_EQ(v.limit_detail.rfind("controller_current_limit at km 0.0", 0), 0u) << v.limit_detail;
  // From lap 2 on (at speed), only on the climb: 600..850 m of each lap, and a little
  // after it while the car gets back to speed.
  for (size_t k = 0; k < r.rec.samples(); ++k) {
    const double s_m = r.rec.vehicle_distance_m[k];
    if (s_m < 1600.0 || r.rec.vehicle_limit[k] != static_cast<uint8_t>(DriveLimit::ControllerCurrent)) continue;
    const double inLap = std::fmod(s_m, 1600.0);
    EXPECT_GT(inLap, 600.0) << s_m;
    EXPECT_LT(inLap, 1100.0) << s_m;
  }
  EXPECT_NEAR(test::eventTime(r, "vehicle_limited"), v.limit_time_s, 1e-12);
  // The pack current stays at the controller's limit: the drive's power is set where
  // the limit meets the pack's E - R·I at each tick's start, and within the tick the
  // pack's EMF drifts by microvolts.
  const auto& i = r.rec.pack_current_A;
  EXPECT_LT(*std::max_element(i.begin(), i.end()), 12.0 + 1e-5);
  // The time lost is the sum of the laps' (each against the reference car's lap).
  double lostLaps = 0.0;
  for (const LapRecord& l : v.laps) lostLaps += l.time_s - l.reference_time_s;
  const double lost = v.time_s - v.reference_time_s;
  EXPECT_GT(lost, 10.0);
  EXPECT_NEAR(lostLaps, lost, 1e-6);
  const std::string text = formatSummary(s, r);
  char line[64];
  std::snprintf(line, sizeof line, "time lost       %.1f s", lost);
  EXPECT_NE(text.find(line), std::string::npos) << text;
  EXPECT_NE(text.find("pack limit      first at"), std::string::npos);
}

TEST(VehicleRace, TheTimeLostLineTimesTheReferenceFromSettingOff) {
  // The solar car (100 ms tick) sets off at 0.30 s, when its BMS is ready. The vehicle line
  // said "finished ... in 112.3 s" (from setting off) and the time-lost line "0.0 s against
  // the same driver ... (112.6 s)": the reference's finishing time on the run's clock, so the
  // two times of one race differed by the 0.3 s before setting off. Now both count from
  // setting off: the reference's time is the vehicle's less the time lost.
  const Scenario s = loadScenarioFileWithOverrides(
      race("solar_car_28s15p_stage"),
      {{"load.route", "{segments: [{length_m: 2000, speed_kmh: 80}], laps: 1}"}, {"expect", "{}"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  ASSERT_GT(v.start_s, 0.25);
  const std::string text = formatSummary(s, r);
  double driven = 0, lost = 0, ref = 0;
  const size_t a = text.find(" in ", text.find("vehicle         finished"));
  const size_t b = text.find("time lost       ");
  ASSERT_NE(a, std::string::npos) << text;
  ASSERT_NE(b, std::string::npos) << text;
  ASSERT_EQ(std::sscanf(text.c_str() + a, " in %lf s", &driven), 1) << text;
  ASSERT_EQ(std::sscanf(text.c_str() + b, "time lost %lf s against the same driver on a pack that never limits it (%lf s)", &lost, &ref), 2)
      << text;
  EXPECT_NEAR(driven - lost, ref, 0.11) << text;  // each printed to 0.1 s
  EXPECT_NEAR(ref, v.reference_time_s - v.start_s, 0.051) << text;
}

TEST(VehicleRace, AStageRaceSetsOffAtStageOnesStartNotAtTheReadyLight) {
  // The solar car ready at 0.30 s, its stage 1 at 13:00 with the sun's clock at 12:54 at
  // t = 0: it waits 360 s at the start line. The vehicle line said "set off at 0.30 s (BMS
  // ready)", its time and average speed and lap 1's time (637.0 s, 16.95 km/h for 3 km)
  // counted that wait, and so would a time limit. Now the race and lap 1 begin when stage 1
  // sets off; the wait's energy (the array charging the parked pack) is its own line, so
  // the laps and it still add up to the run's.
  const Scenario s = loadScenarioFileWithOverrides(
      race("solar_car_28s15p_stage"),
      {{"pack.initial_soc", "0.6"},
       {"load.route", "{laps: 2, segments: [{length_m: 1500, speed_kmh: 70}, {length_m: 1500, speed_kmh: 60}], "
                      "stages: [{end_km: 3.5, start_hour: 13.0, day: 1}, {end_km: 6, start_hour: 13.1, day: 1}]}"},
       {"load.sun.start_solar_hour", "12.9"}, {"expect", "{}"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  ASSERT_EQ(v.stages.size(), 2u);
  const double t1 = (13.0 - 12.9) * 3600.0;  // stage 1's start on the run's clock
  EXPECT_NEAR(v.ready_s, 0.3, 1e-9);
  EXPECT_GE(v.start_s, t1 - 1e-9);
  EXPECT_LT(v.start_s, t1 + 0.1 + 1e-9);  // the first tick at or after it
  EXPECT_NEAR(v.start_s, v.stages[0].depart_s, 1e-9);
  ASSERT_FALSE(v.laps.empty());
  EXPECT_NEAR(v.laps[0].start_s, v.start_s, 1e-9);
  // lap 1 is 3 km driven at 60-70 km/h: well under 3 minutes, not the 6-minute wait more
  EXPECT_LT(v.laps[0].time_s, 200.0);
  double pack_Wh = v.prestart_pack_Wh, array_Wh = v.prestart_array_Wh;
  for (const LapRecord& l : v.laps) {
    pack_Wh += l.pack_Wh;
    array_Wh += l.array_Wh;
  }
  // (to the finish line; the run's totals hold the rest of its last tick, 0.1 s)
  EXPECT_NEAR(pack_Wh, v.pack_Wh, 0.01);
  EXPECT_NEAR(array_Wh, v.array_Wh, 0.01);
  EXPECT_LT(v.prestart_pack_Wh, -1.0);  // the array charged the waiting pack
  const std::string text = formatSummary(s, r);
  EXPECT_NE(text.find("s (stage 1's start; the BMS ready at 0.30 s)"), std::string::npos) << text;
  EXPECT_NE(text.find("before setting off, 359.7 s at the start line"), std::string::npos) << text;
  EXPECT_NEAR(r.summary.vehicle.time_s - v.start_s, v.time_s - v.stages[0].depart_s, 1e-9);
}

TEST(VehicleRace, APackLimitLineCountsOnlyThePacksShareOfTheCut) {
  // The cold scooter from 30 % on a hilly loop with a control stop: setting off again it
  // wants 980 W, its 720 W motor gives 720 W, and the controller's fold-back at 32.89 V
  // takes a milliwatt more. The line said "the drive got 720.00 W of the 980.29 W the
  // driver wanted, 260 W short (pack 32.89 V, ...)": the motor's own 260 W laid on the
  // pack. Now the shortfall is against what the motor (or the driver's cap) left, and the
  // driver's wish is said beside it.
  const auto dir = test::processTempDir("pack_limit_share");
  const auto csv = dir / "hill.csv";
  {
    std::ofstream out(csv);
    out << "distance_m;elevation_m;speed_kmh\n0;50,0;25\n400;50,0;25\n700;62,5;20\n1000;50,0;30\n1500;50,0;25\n";
  }
  const Scenario s = loadScenarioFileWithOverrides(
      race("scooter_16s_lto_range_cold"),
      {{"pack.initial_soc", "0.3"},
       {"load.route", "{csv: " + csv.string() + ", segments: [], laps: 40, stops: [{at_km: 2.2, duration_s: 120}]}"},
       {"run.duration_s", "800"}, {"expect", "{}"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.limited);
  ASSERT_EQ(v.limit_detail.rfind("low_voltage_foldback", 0), 0u) << v.limit_detail;
  const size_t at = v.limit_detail.find("the drive got ");
  ASSERT_NE(at, std::string::npos) << v.limit_detail;
  double got = 0, allowed = 0, wanted = 0, shortW = 0;
  ASSERT_EQ(std::sscanf(v.limit_detail.c_str() + at,
                        "the drive got %lf W of the %lf W the motor allowed (the driver wanted %lf W), %lf W short", &got,
                        &allowed, &wanted, &shortW),
            4)
      << v.limit_detail;
  EXPECT_NEAR(allowed, 720.0, 1e-9);  // vehicle.max_drive_power_W
  EXPECT_GT(wanted, allowed + 100.0);
  EXPECT_LE(got, allowed);
  EXPECT_NEAR(shortW, allowed - got, 0.01) << v.limit_detail;
}

TEST(VehicleRace, ATripLeavesTheCarCoastingAsTheRoadLoadSays) {
  // The E-switch at 30 s opens the pack on the first flat (at ~210 m of 600 m): no
  // power; the car coasts, m·dv/dt = -(F_r + k·v²), F_r = m·g·C_rr, k = ½·ρ·CdA, so
  // v(t) = √(F_r/k)·tan(atan(v0·√(k/F_r)) - √(F_r·k)·t/m).
  const Scenario s = loadScenarioFileWithOverrides(
      race("eco_marathon_12s_circuit"), {{"faults", "[{kind: estop, switch: internal, at_s: 30}]"},
                                         {"expect", "{}"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(r.summary.tripped);
  ASSERT_TRUE(v.limited);
  EXPECT_EQ(v.limit_detail.rfind("pack_shortfall", 0), 0u) << v.limit_detail;
  EXPECT_GE(v.limit_time_s, 30.0);
  EXPECT_LE(v.limit_time_s, 30.02);  // the relay opens within a tick or two of the switch
  const size_t k0 = test::sampleAt(r.rec, 31.0), k1 = test::sampleAt(r.rec, 81.0);
  const double v0 = r.rec.vehicle_speed_m_per_s[k0];
  const double fr = 220.0 * kG * 0.006, kd = 0.5 * 1.2 * 0.25;
  const double v1 = std::sqrt(fr / kd) * std::tan(std::atan(v0 * std::sqrt(kd / fr)) - std::sqrt(fr * kd) * 50.0 / 220.0);
  ASSERT_LT(r.rec.vehicle_distance_m[k1], 600.0);  // still on the flat
  EXPECT_NEAR(r.rec.vehicle_speed_m_per_s[k1], v1, 0.01 * v1);
  EXPECT_FALSE(v.finished);
  const std::string text = formatSummary(s, r);
  EXPECT_NE(text.find("pack limit      first at 30.0"), std::string::npos) << text;
  EXPECT_NE(text.find("distance        0."), std::string::npos) << text;  // still rolling at the run's end
  EXPECT_NE(text.find("when the run ended (the route not finished)"), std::string::npos) << text;
}

TEST(VehicleRace, AShortfallLineGivesWhatThePackWasAskedAndGave) {
  // The E-switch at 30 s with a 1 m² array at noon: the relay open, the array alone feeds
  // the bus. The line said "the drive got 185.25 W of the 188.85 W it asked the pack for",
  // but the pack was asked the drive + 8 W aux less the array (/vehicle/pack_request_W):
  // 6.51 W. Now each figure is the record's: what the pack was asked at that tick and
  // gave (the relay opening inside the tick), and what the drive got (that and the
  // array, less the auxiliaries).
  const Scenario s = loadScenarioFileWithOverrides(
      race("eco_marathon_12s_circuit"),
      {{"faults", "[{kind: estop, switch: internal, at_s: 30}]"},
       {"load.sun", "{array_area_m2: 1, efficiency: 0.2, latitude_deg: 45, day_of_year: 172, start_solar_hour: 12}"},
       {"bms.charge_full_cell_V", "null"}, {"output.interval_s", "0.01"}, {"run.stop_after_trip_s", "10"}, {"expect", "{}"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.limited);
  ASSERT_EQ(v.limit_detail.rfind("pack_shortfall", 0), 0u) << v.limit_detail;
  const size_t at = v.limit_detail.find("the drive got ");
  ASSERT_NE(at, std::string::npos) << v.limit_detail;
  double got = 0, wanted = 0, gave = -1, asked = 0;
  ASSERT_EQ(std::sscanf(v.limit_detail.c_str() + at,
                        "the drive got %lf W of the %lf W it asked for (the pack gave %lf W of the %lf W asked of it)", &got,
                        &wanted, &gave, &asked),
            4)
      << v.limit_detail;
  const size_t k = test::sampleAt(r.rec, v.limit_time_s);  // the plan for the tick the limit acted in
  EXPECT_NEAR(asked, r.rec.vehicle_pack_request_W[k], 0.01) << v.limit_detail;
  // the array over that tick: the interval that ends at the next sample (0.01 s apart)
  const double array_W = r.rec.vehicle_array_W[k + 1];
  ASSERT_GT(array_W, 100.0);
  EXPECT_NEAR(array_W, r.rec.vehicle_array_available_W[k + 1], 1e-6);  // the relay open: the drive took it all
  EXPECT_NEAR(asked, wanted + 8.0 - array_W, 0.01) << v.limit_detail;  // drive + aux - array
  EXPECT_LT(gave, asked - 1.0) << v.limit_detail;                      // the relay opened in the tick
  EXPECT_NEAR(got, gave + array_W - 8.0, 0.01) << v.limit_detail;      // pack + array less the aux
}

TEST(VehicleRace, TheArrayChannelIsThePowerTheBusTookWhenThePackRefusesTheCharge) {
  // The eco car at the start under a 2 m² array at noon on the equator: 400 W into
  // a pack whose BMS trips at 5 A of charge. It trips at 0.23 s and the relay opens; from
  // then on the array feeds only the drive and the auxiliaries. /vehicle/array_W recorded
  // the MPPT's planned 395 W throughout: its integral was 3.50 Wh against the summary's
  // 3.03 Wh of array energy taken (a probe saw 13.84 against 12.07 Wh). Now it is the mean
  // power taken over each recording interval, and /vehicle/array_available_W is what the
  // MPPT had: the record integrates to the summary and the lap table at any interval.
  for (const char* interval : {"0.01", "0.5"}) {
    const Scenario s = loadScenarioFileWithOverrides(
        race("eco_marathon_12s_circuit"),
        {{"load.sun", "{array_area_m2: 2, efficiency: 0.2, latitude_deg: 0, day_of_year: 80, start_solar_hour: 12}"},
         {"bms.charge_full_cell_V", "0"}, {"output.interval_s", interval}, {"run.solver", "fast"},
         {"run.stop_after_trip_s", "30"}, {"expect", "{}"}});
    const RunResult r = runScenario(s);
    const VehicleSummary& v = r.summary.vehicle;
    const Recording& rec = r.rec;
    ASSERT_TRUE(r.summary.tripped) << interval;
    double taken_J = 0.0, avail_J = 0.0;
    for (size_t i = 1; i < rec.time_s.size(); ++i) {  // each sample: the mean since the one before
      const double span = rec.time_s[i] - rec.time_s[i - 1];
      taken_J += rec.vehicle_array_W[i] * span;
      avail_J += rec.vehicle_array_available_W[i] * span;
      EXPECT_LE(rec.vehicle_array_W[i], rec.vehicle_array_available_W[i] + 1e-6) << interval << " at " << rec.time_s[i];
    }
    EXPECT_NEAR(taken_J / 3600.0, v.array_Wh, 1e-9 * avail_J) << interval;
    double laps_Wh = 0.0;
    for (const LapRecord& l : v.laps) laps_Wh += l.array_Wh;
    EXPECT_NEAR(laps_Wh, v.array_Wh, 1e-9) << interval;
    // The MPPT had 400 W the whole time; the bus took less once the relay opened.
    EXPECT_GT(avail_J / 3600.0, v.array_Wh + 0.3) << interval;
    const double open_s = test::eventTime(r, "relay");
    ASSERT_GT(open_s, 0.0);
    // the last interval: the pack isolated, the car cruising on about 200 W of the array's 400
    const size_t k = rec.time_s.size() - 1;
    EXPECT_LT(rec.vehicle_array_W[k], rec.vehicle_array_available_W[k] - 10.0) << interval;
    EXPECT_GT(rec.vehicle_array_available_W[k], 350.0) << interval;
  }
}

TEST(VehicleRace, SolarArrayEnergyIsTheClearSkyIntegral) {
  // A 0.5 m² array at 20 % through a 95 % MPPT on the eco car, 45° N on day 172 from
  // 11:00 solar time: its energy is the integral of the clear-sky formula over the race,
  // and the pack gives that much less.
  const Scenario plain = loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"), {{"run.solver", "fast"}});
  const Scenario sunny = loadScenarioFileWithOverrides(
      race("eco_marathon_12s_circuit"),
      {{"run.solver", "fast"},
       {"load.sun", "{array_area_m2: 0.5, efficiency: 0.2, mppt_efficiency: 0.95, latitude_deg: 45, day_of_year: 172, "
                    "start_solar_hour: 11}"}});
  const RunResult a = runScenario(plain), b = runScenario(sunny);
  const VehicleSummary& v = b.summary.vehicle;
  ASSERT_TRUE(v.finished);
  // The formula again (docs/vehicle.md), by the trapezoid rule over the set-off .. finish.
  const double pi = std::acos(-1.0), deg = pi / 180.0;
  const double decl = 23.45 * deg * std::sin(2.0 * pi * (284.0 + 172.0) / 365.0);
  auto g = [&](double t) {
    const double h = 11.0 + t / 3600.0;
    const double cz = std::sin(45 * deg) * std::sin(decl) + std::cos(45 * deg) * std::cos(decl) * std::cos((h - 12) * 15 * deg);
    return cz <= 0 ? 0.0 : 1.1 * 1353.0 * std::pow(0.7, std::pow(1.0 / cz, 0.678)) * cz;
  };
  double e_J = 0.0;
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    const double t0 = v.start_s + (v.time_s - v.start_s) * k / n, t1 = v.start_s + (v.time_s - v.start_s) * (k + 1) / n;
    e_J += 0.5 * (g(t0) + g(t1)) * (t1 - t0);
  }
  const double array_Wh = 0.5 * 0.2 * 0.95 * e_J / 3600.0;
  EXPECT_GT(array_Wh, 30.0);
  EXPECT_NEAR(v.array_Wh, array_Wh, 0.02 * array_Wh);
  EXPECT_NEAR(a.summary.vehicle.pack_Wh - v.pack_Wh, array_Wh, 0.02 * array_Wh);
}

namespace {
// Scooter (scooter_16s_lto_range*.yaml): 100 kg, C_rr 0.01, CdA 0.6, η 0.8, aux 10 W, 25 km/h
// on 1 km laps.
double scooterLap_Wh(double rho) {
  const double v = 25.0 / 3.6;
  return (force_N(100, 0.01, rho, 0.6, v, 0.0) * 1000.0 / 0.8 + 10.0 * 1000.0 / v) / 3600.0;
}
}  // namespace

TEST(VehicleRace, ScooterRangeAtCruiseHotAndCold) {
  // From 25 % charge (the bundled rides start at 90 %: the same physics, a quarter the run).
  const Overrides o{{"pack.initial_soc", "0.25"}, {"expect", "{}"}};
  const RunResult warm = runScenario(loadScenarioFileWithOverrides(race("scooter_16s_lto_range"), o));
  const RunResult cold = runScenario(loadScenarioFileWithOverrides(race("scooter_16s_lto_range_cold"), o));
  // Air at 25 C (1.184 kg/m³) and -15 C (1.367 kg/m³): 9.753 and 10.672 Wh a lap.
  for (const auto& [r, rho] : {std::pair<const RunResult&, double>{warm, 1.184}, {cold, 1.367}}) {
    const VehicleSummary& v = r.summary.vehicle;
    ASSERT_FALSE(v.finished);
    ASSERT_GE(v.laps.size(), 6u);
    int cruise = 0;
    for (size_t i = 1; i < v.laps.size(); ++i)  // laps at cruise: ended before the first limit
      if (v.laps[i].start_s + v.laps[i].time_s < v.limit_time_s && ++cruise)
        EXPECT_NEAR(v.laps[i].pack_Wh, scooterLap_Wh(rho), 0.02 * scooterLap_Wh(rho)) << "lap " << i + 1;
    EXPECT_GE(cruise, 4);
    // It ends standing, folded back, not tripped. The fold-back (40 A · (V − 32)/1.6 V)
    // cuts the cruise power P = 245.8 W (266.8 W cold) once V·I_allowed(V) < P, below
    // V_cut = 32 + 1.6·P/(40·V): before the first limit every recorded voltage is above it.
    const double p_W = scooterLap_Wh(rho) * 3600.0 / 144.0;
    double vCut = 33.0;
    for (int it = 0; it < 50; ++it) vCut = 32.0 + 1.6 * p_W / (40.0 * vCut);
    EXPECT_TRUE(v.stood_still);
    EXPECT_FALSE(r.summary.tripped);
    EXPECT_EQ(v.limit_detail.rfind("low_voltage_foldback", 0), 0u) << v.limit_detail;
    EXPECT_GE(test::eventTime(r, "vehicle_stopped"), v.limit_time_s);
    for (size_t k = 0; k < r.rec.samples(); ++k) {
      if (r.rec.time_s[k] < v.limit_time_s - 0.01) EXPECT_GT(r.rec.pack_voltage_V[k], vCut) << r.rec.time_s[k];
      else if (r.rec.time_s[k] > v.limit_time_s && r.rec.vehicle_speed_m_per_s[k] == 0.0)
        EXPECT_LT(r.rec.pack_voltage_V[k], vCut) << r.rec.time_s[k];
    }
  }
  EXPECT_NEAR(scooterLap_Wh(1.184), 9.753, 0.001);
  // Colder: denser air and a stiffer pack, a shorter range.
  EXPECT_LT(cold.summary.vehicle.distance_m, warm.summary.vehicle.distance_m);
}

TEST(VehicleRace, ASweepOverSpeedFindsTheFastestThatFinishes) {
  // 10 km on the scooter from 25 % charge, the driver's speed capped at 20, 30, 40 km/h.
  // A km costs (F_r + k·v²)/η + P_aux/v: 12.30 Wh at 30 km/h, 18.88 Wh at 40 (hand, with
  // ρ = 1.184); 30 km/h finishes, 40 km/h stands still short of the line -- and the
  // energy the pack gave the 40 km/h ride would have carried it over the line at 30.
  auto wh_per_km = [](double kmh) {
    const double v = kmh / 3.6;
    return (force_N(100, 0.01, 1.184, 0.6, v, 0.0) * 1000.0 / 0.8 + 10.0 * 1000.0 / v) / 3600.0;
  };
  EXPECT_NEAR(wh_per_km(30), 12.30, 0.01);
  EXPECT_NEAR(wh_per_km(40), 18.88, 0.01);
  std::vector<RunResult> runs;
  for (double v : {20.0, 30.0, 40.0})
    runs.push_back(runScenario(loadScenarioFileWithOverrides(
        race("scooter_16s_lto_range"), {{"pack.initial_soc", "0.25"}, {"expect", "{}"}, {"load.route.laps", "10"},
                                        {"load.route.segments", "[{length_m: 1000, speed_kmh: 60}]"},
                                        {"load.driver.max_speed_kmh", std::to_string(v)}})));
  EXPECT_TRUE(runs[0].summary.vehicle.finished);
  EXPECT_TRUE(runs[1].summary.vehicle.finished);
  const VehicleSummary& fast = runs[2].summary.vehicle;
  ASSERT_FALSE(fast.finished);
  EXPECT_TRUE(fast.stood_still);
  EXPECT_GT(fast.pack_Wh / wh_per_km(30), 10.0);
  EXPECT_LT(fast.pack_Wh / wh_per_km(40), 10.0);
  // Faster is quicker while it lasts: 30 km/h covers the 10 km in 1200 s plus the start.
  EXPECT_NEAR(runs[1].summary.vehicle.time_s - runs[1].summary.vehicle.start_s, 1200.0, 6.0);
}

TEST(VehicleRace, BadVehicleKeysNameFileLineAndRange) {
  const auto dir = test::processTempDir("vehicle_keys");
  const auto file = dir / "bad.yaml";
  {
    std::ofstream out(file);
    out << "extends: " << race("scooter_16s_lto_range") << "\n"
        << "load:\n"
        << "  vehicle:\n"
        << "    mass_kg: -3\n";
  }
  const std::string e = test::fileErrorOf(file);
  EXPECT_NE(e.find("bad.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("load.vehicle.mass_kg"), std::string::npos) << e;
  EXPECT_NE(e.find("(0, 100000]"), std::string::npos) << e;
  const std::string fold = test::scenarioErrorOf(
      [] { loadScenarioFileWithOverrides(race("scooter_16s_lto_range"), {{"load.vehicle.cutoff_end_V", "40"}}); });
  EXPECT_NE(fold.find("load.vehicle.cutoff_end_V: must be below cutoff_start_V (33.6 V)"), std::string::npos) << fold;
  const std::string key = test::scenarioErrorOf(
      [] { loadScenarioFileWithOverrides(race("scooter_16s_lto_range"), {{"load.driver.max_speed", "30"}}); });
  EXPECT_NE(key.find("max_speed_kmh"), std::string::npos) << key;
  // A one-way discharge path cannot take the array's charge.
  const std::string sun = test::scenarioErrorOf([] {
    loadScenarioFileWithOverrides(race("scooter_16s_lto_range"),
                                  {{"load.sun", "{array_area_m2: 1, efficiency: 0.2, latitude_deg: 0, day_of_year: 80, "
                                                "start_solar_hour: 9}"}});
  });
  EXPECT_NE(sun.find("fet_paths: separate"), std::string::npos) << sun;
}

TEST(VehicleRace, NoReadyLightNoRace) {
  // Without the drive-enable input the BMS stays in standby: the car never sets off and the
  // run ends after standstill_end_s (not after 30 days of simulated standing).
  const Scenario s = loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"),
                                                   {{"bms.run_request", "false"}, {"expect", "{}"},
                                                    {"load.standstill_end_s", "5"}});
  const RunResult r = runScenario(s);
  EXPECT_NEAR(test::eventTime(r, "vehicle_stopped", "never set off"), 5.0, 0.011);
  EXPECT_EQ(r.summary.vehicle.distance_m, 0.0);
  EXPECT_NEAR(r.summary.energy_delivered_Wh, 0.0, 1e-9);
  EXPECT_NE(formatSummary(s, r).find("range           0.000 km: it never set off"), std::string::npos);
}

TEST(VehicleRace, RegenerationOnTheDescentComesOffTheLapBudget) {
  // With 150 W of regeneration the descent (-3 %: F = -43.3 N at 27 km/h, -325 W at the
  // wheel, -276 W after η) returns the capped 150 W for its 33.3 s: 1.389 Wh a lap less.
  const Scenario s = loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"),
                                                   {{"load.vehicle.max_regen_power_W", "150"}, {"run.solver", "fast"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  const double down_N = force_N(220, 0.006, 1.2, 0.25, kEcoV, -0.03);
  EXPECT_LT(down_N * kEcoV * 0.85, -150.0);  // the cap binds
  const double lap_Wh = (ecoLapPack_J() - 150.0 * 250.0 / kEcoV) / 3600.0;
  EXPECT_NEAR(lap_Wh, 13.80, 0.01);
  for (size_t i = 1; i < v.laps.size(); ++i) EXPECT_NEAR(v.laps[i].pack_Wh, lap_Wh, 0.02 * lap_Wh) << "lap " << i + 1;
  // The pack is charged on the descent: 142 W net of the 8 W aux.
  const auto& i = r.rec.pack_current_A;
  EXPECT_LT(*std::min_element(i.begin(), i.end()), -142.0 / 50.4);
  EXPECT_FALSE(r.summary.tripped);
}

namespace {
// Clear-sky global horizontal irradiance (docs/vehicle.md), written out again.
double clearSky(double lat, int day, double hour) {
  const double pi = std::acos(-1.0), deg = pi / 180.0;
  const double decl = 23.45 * deg * std::sin(2.0 * pi * (284.0 + day) / 365.0);
  const double cz = std::sin(lat * deg) * std::sin(decl) + std::cos(lat * deg) * std::cos(decl) * std::cos((hour - 12) * 15 * deg);
  return cz <= 0 ? 0.0 : 1.1 * 1353.0 * std::pow(0.7, std::pow(1.0 / cz, 0.678)) * cz;
}
}  // namespace

TEST(VehicleRace, SolarStageRoadLoadIsPackPlusArray) {
  // solar_car_28s15p_stage.yaml: 300 kg, C_rr 0.005, CdA 0.09, ρ 1.16, η 0.95, aux 20 W,
  // 80 km/h over 120 km flat, 10 km at +2 %, 10 km at -2 % (regeneration, below its cap);
  // 4 m² × 24 % × 98 % at 12.5° S on day 296 from 13:00 solar time.
  const Scenario s = loadScenarioFile(race("solar_car_28s15p_stage"));
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  const double sp = 80.0 / 3.6;
  const double flat = force_N(300, 0.005, 1.16, 0.09, sp, 0.0), up = force_N(300, 0.005, 1.16, 0.09, sp, 0.02),
               down = force_N(300, 0.005, 1.16, 0.09, sp, -0.02);
  ASSERT_LT(down, 0.0);
  ASSERT_GT(down * sp * 0.95, -2000.0);  // regeneration below its cap
  const double drive_J = (flat * 120e3 + up * 10e3) / 0.95 + down * 10e3 * 0.95 + 0.5 * 300 * sp * sp / 0.95 +
                         20.0 * (v.time_s - v.start_s);
  EXPECT_NEAR(drive_J / 3600.0, 1719.0, 5.0);
  // What the drive and the aux used came from the pack and the array.
  EXPECT_NEAR(v.pack_Wh + v.array_Wh, drive_J / 3600.0, 0.02 * drive_J / 3600.0);
  // The array: the clear-sky integral over the stage (trapezoids of 10 s).
  double e_J = 0.0;
  for (double t = v.start_s; t < v.time_s; t += 10.0) {
    const double t1 = std::min(t + 10.0, v.time_s);
    e_J += 0.5 * (clearSky(-12.5, 296, 13 + t / 3600) + clearSky(-12.5, 296, 13 + t1 / 3600)) * (t1 - t);
  }
  const double array_Wh = 4.0 * 0.24 * 0.98 * e_J / 3600.0;
  EXPECT_NEAR(v.array_Wh, array_Wh, 0.02 * array_Wh);
  EXPECT_FALSE(v.limited);
}

TEST(VehicleRace, ThePackFullTheBmsEndsTheArraysCharge) {
  // From 98 % at noon and 50 km/h (the drive ~380 W, the array ~980 W) the array charges
  // the pack past 4.20 V a cell: the BMS's over-voltage trip opens the relay, as it would
  // end a charger's charge.
  const Scenario s = loadScenarioFileWithOverrides(
      race("solar_car_28s15p_stage"), {{"pack.initial_soc", "0.98"}, {"expect", "{}"}, {"load.driver.max_speed_kmh", "50"},
                                       {"load.sun.start_solar_hour", "12"}});
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_NE(r.summary.trip_reason.find("cell_overvoltage"), std::string::npos) << r.summary.trip_reason;
  const double trip_s = r.summary.trip_time_s;
  double charge_A = 0.0;
  for (size_t k = 0; k < r.rec.samples(); ++k) {
    if (r.rec.time_s[k] < trip_s) charge_A = std::min(charge_A, r.rec.pack_current_A[k]);
    else if (r.rec.time_s[k] > trip_s + 1.0) EXPECT_EQ(r.rec.pack_current_A[k], 0.0) << r.rec.time_s[k];
  }
  EXPECT_LT(charge_A, -1.0);  // it was charging before
}

TEST(VehicleRace, SameScenarioSameBits) {
  const Scenario s = loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"),
                                                   {{"load.vehicle.max_current_A", "12"}, {"run.duration_s", "300"}});
  const RunResult a = runScenario(s), b = runScenario(s);
  ASSERT_GT(a.rec.samples(), 100u);
  EXPECT_EQ(a.rec.vehicle_distance_m, b.rec.vehicle_distance_m);
  EXPECT_EQ(a.rec.vehicle_speed_m_per_s, b.rec.vehicle_speed_m_per_s);
  EXPECT_EQ(a.rec.vehicle_pack_request_W, b.rec.vehicle_pack_request_W);
  EXPECT_EQ(a.rec.pack_current_A, b.rec.pack_current_A);
  EXPECT_EQ(formatSummary(s, a), formatSummary(s, b));
}

namespace {
// The two-day race cut to two 20 km stages at 90 km/h on one day: stage 1 from 12:00
// solar time (t = 0), stage 2 sets off at 13:00, so the car stands ~33 min at the end
// of stage 1 with its array charging the pack.
Scenario shortStages(std::vector<std::pair<std::string, std::string>> more = {}) {
  std::vector<std::pair<std::string, std::string>> o = {
      {"load.route.segments", "[{length_m: 40000, speed_kmh: 90}]"},
      {"load.route.stages", "[{end_km: 20, start_hour: 12}, {end_km: 40, start_hour: 13, day: 1}]"},
      {"load.route.stops", "[]"},
      {"load.sun.start_solar_hour", "12"},
      {"expect", "{}"}};
  o.insert(o.end(), more.begin(), more.end());
  return loadScenarioFileWithOverrides(test::scenarioDir() + "/../examples/vehicle/solar_car_28s15p_two_day.yaml", o);
}
}  // namespace

TEST(VehicleRace, ParkedBetweenStagesTheArrayChargesThePack) {
  const Scenario s = shortStages();
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  ASSERT_EQ(v.stages.size(), 2u);
  const StageRecord& a = v.stages[0];
  const StageRecord& b = v.stages[1];
  EXPECT_TRUE(a.complete && b.complete);
  EXPECT_NEAR(a.distance_m, 20000.0, 0.01);  // it stands at the stage's end
  EXPECT_NEAR(b.depart_s, 3600.0, 0.11);      // 13:00 solar time
  EXPECT_NEAR(a.depart_s + a.time_s + a.parked_s, b.depart_s, 1e-6);
  // Parked: the clear-sky integral over the stop through 4 m² x 24 % x 98 % went into the
  // pack, nothing out (no aux between stages): pack energy out = -array energy.
  double e_J = 0.0;
  const double t0 = a.depart_s + a.time_s, t1 = b.depart_s;
  for (double t = t0; t < t1; t += 10.0) {
    const double u = std::min(t + 10.0, t1);
    e_J += 0.5 * (clearSky(-12.5, 296, 12 + t / 3600) + clearSky(-12.5, 296, 12 + u / 3600)) * (u - t);
  }
  const double parked_Wh = 4.0 * 0.24 * 0.98 * e_J / 3600.0;
  EXPECT_GT(parked_Wh, 400.0);
  EXPECT_NEAR(a.parked_array_Wh, parked_Wh, 0.02 * parked_Wh);
  EXPECT_NEAR(a.parked_pack_Wh, -a.parked_array_Wh, 1e-3 * a.parked_array_Wh);
  // Each stage: the road load of 20 km at 90 km/h from a standstill came from the pack
  // and the array. Stage 1 ends braking to a standstill at 1 m/s²: the wheels give back
  // (m·b − F_res(v))·v, of which the drive returns η of it up to the 2 kW regeneration
  // cap (integrated here over v(t) = v0 − b·t); stage 2 ends at the finish line at speed.
  const double sp = 90.0 / 3.6;
  const double flat_N = force_N(300, 0.005, 1.16, 0.09, sp, 0.0);
  double regen_J = 0.0, brakeRoad_J = 0.0;
  for (double t = 0.0; t < sp; t += 0.001) {
    const double vm = sp - (t + 0.0005);
    const double back_W = (300.0 * 1.0 - force_N(300, 0.005, 1.16, 0.09, vm, 0.0)) * vm;
    regen_J += std::min(0.95 * back_W, 2000.0) * 0.001;
    brakeRoad_J += vm * 0.001;
  }
  const double kinetic_J = 0.5 * 300 * sp * sp / 0.95;
  const double stage1_J = flat_N * (20000.0 - brakeRoad_J) / 0.95 + kinetic_J - regen_J + 20.0 * a.time_s;
  const double stage2_J = flat_N * 20000.0 / 0.95 + kinetic_J + 20.0 * b.time_s;
  EXPECT_NEAR(a.pack_Wh + a.array_Wh, stage1_J / 3600.0, 0.02 * stage1_J / 3600.0);
  EXPECT_NEAR(b.pack_Wh + b.array_Wh, stage2_J / 3600.0, 0.02 * stage2_J / 3600.0);
  // The stages and the stop add up to the race's pack energy, but for the last tick (the
  // run ends at the first tick past the finish line: at most 0.1 s of ~2 kW).
  EXPECT_NEAR(a.pack_Wh + a.parked_pack_Wh + b.pack_Wh, v.pack_Wh, 0.06);
  // The summary's stage table and the events.
  const std::string text = formatSummary(s, r);
  EXPECT_NE(text.find("day 1 13:00"), std::string::npos) << text;
  EXPECT_NE(test::eventTime(r, "vehicle_stop", "stage 1 ended at km 20.000"), -1.0);
}

TEST(VehicleRace, TheBmsFullReadingEndsTheArraysChargeWhileParked) {
  // From 90 % the parked array charges the pack until the BMS reads 4.15 V on its highest
  // module: then the array charges it no more (bounded by the BMS, not by the sun).
  const Scenario s = shortStages({{"pack.initial_soc", "0.9"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  ASSERT_GE(v.array_full_s, 0.0);
  EXPECT_FALSE(r.summary.tripped);
  const StageRecord& a = v.stages[0];
  const double arrive_s = a.depart_s + a.time_s;
  ASSERT_GT(v.array_full_s, arrive_s);
  ASSERT_LT(v.array_full_s, v.stages[1].depart_s);
  // After the full reading and until the car sets off: no charge current.
  double maxV = 0.0;
  for (size_t k = 0; k < r.rec.samples(); ++k) {
    const double t = r.rec.time_s[k];
    if (t > v.array_full_s + 0.2 && t < v.stages[1].depart_s) EXPECT_GE(r.rec.pack_current_A[k], -1e-6) << t;
    for (size_t c = 0; c < static_cast<size_t>(r.rec.cells); ++c)
      maxV = std::max(maxV, r.rec.cell_voltage_V[k * static_cast<size_t>(r.rec.cells) + c]);
  }
  EXPECT_LT(maxV, 4.20);  // the over-voltage protection never had to act
  // The array's energy while parked is below the clear-sky integral over the stop.
  double e_J = 0.0;
  for (double t = arrive_s; t < v.stages[1].depart_s; t += 10.0) {
    const double u = std::min(t + 10.0, v.stages[1].depart_s);
    e_J += 0.5 * (clearSky(-12.5, 296, 12 + t / 3600) + clearSky(-12.5, 296, 12 + u / 3600)) * (u - t);
  }
  EXPECT_LT(a.parked_array_Wh, 0.9 * 4.0 * 0.24 * 0.98 * e_J / 3600.0);
  EXPECT_NE(test::eventTime(r, "vehicle_stop", "array charge ended"), -1.0);
}

TEST(VehicleRace, ARouteCsvWithElevationAndWindGivesTheHandLapBudget) {
  // The eco circuit as a table of elevations (+7.5 m over 250 m: 3 %) into a 10 km/h
  // headwind: the lap costs (F_flat·1100 m + F_up·250 m)/η + aux·t with the air at v + w.
  const auto dir = test::processTempDir("route_csv");
  const auto csv = dir / "circuit.csv";
  {
    std::ofstream out(csv);
    out << "# the eco circuit, by elevation\n"
        << "distance_km,elevation_m,speed_kmh,headwind_kmh\n"
        << "0,100,27,10\n0.6,100,27,10\n0.85,107.5,27,10\n1.1,100,27,10\n1.6,100,27,10\n";
  }
  const Scenario s = loadScenarioFileWithOverrides(
      race("eco_marathon_12s_circuit"),
      {{"run.solver", "fast"}, {"load.route", "{csv: " + csv.string() + ", segments: [], laps: 3}"}, {"expect", "{}"}});
  ASSERT_EQ(s.vehicle.route.segments.size(), 4u);
  // 7.5 m over 250 m of road: sin θ = 0.03, the grade tan θ
  const double up = std::tan(std::asin(0.03));
  EXPECT_NEAR(s.vehicle.route.segments[1].grade, up, 1e-12);
  EXPECT_NEAR(s.vehicle.route.segments[2].grade, -up, 1e-12);
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  const double w = 10.0 / 3.6, air = kEcoV + w;
  auto f = [&](double grade) {
    const double c = 1.0 / std::sqrt(1.0 + grade * grade);
    return 220 * kG * (0.006 * c + grade * c) + 0.5 * 1.2 * 0.25 * air * air;
  };
  ASSERT_LT(f(-up), 0.0);  // downhill the car still brakes
  const double lap_Wh = ((f(0.0) * 1100.0 + f(up) * 250.0) / 0.85 + 8.0 * 1600.0 / kEcoV) / 3600.0;
  EXPECT_GT(lap_Wh, ecoLapPack_J() / 3600.0 * 1.1);  // the wind costs more than 10 %
  for (size_t i = 1; i < v.laps.size(); ++i) EXPECT_NEAR(v.laps[i].pack_Wh, lap_Wh, 0.02 * lap_Wh) << "lap " << i + 1;
}

TEST(VehicleRace, AnElevationTableClimbsItsElevationOverItsRoadDistance) {
  // A straight ramp, 50 m up over 500 m of road (distance_m is along the road, as the
  // vehicle drives it). The grade was taken as 50/500 = 10 % rise over run, so the 500 m
  // of road climbed 500·sin(atan 0.1) = 49.75 m: 0.25 m of m·g·Δh missing, 0.18 Wh of
  // the climb. Now sin θ = 50/500: the climb costs the hand m·g·Δh (and the rolling
  // resistance's cos θ) more than the same road flat, the speed profile alike.
  const auto dir = test::processTempDir("route_csv_ramp");
  auto table = [&](const std::string& name, double top_m) {
    const auto csv = dir / name;
    std::ofstream out(csv);
    out << "distance_m,elevation_m,speed_kmh\n0,100,10\n500," << 100.0 + top_m << ",10\n";
    return csv.string();
  };
  auto run = [&](double top_m) {
    const Scenario s = loadScenarioFileWithOverrides(
        race("eco_marathon_12s_circuit"),
        {{"run.solver", "fast"}, {"load.route", "{csv: " + table("ramp" + std::to_string(top_m) + ".csv", top_m) + ", segments: [], laps: 1}"},
         {"expect", "{}"}});
    EXPECT_NEAR(s.vehicle.route.total_m(), 500.0, 1e-9);  // the route is the road's length
    return runScenario(s).summary.vehicle;
  };
  const VehicleSummary ramp = run(50.0), flat = run(0.0);
  ASSERT_TRUE(ramp.finished && flat.finished);
  EXPECT_FALSE(ramp.limited);  // the same speed profile on both: nothing cut the climb's drive
  EXPECT_NEAR(ramp.distance_m, 500.0, 1e-9);
  EXPECT_NEAR(ramp.time_s - ramp.start_s, flat.time_s - flat.start_s, 1e-6);
  const double sinT = 0.1, cosT = std::sqrt(1.0 - sinT * sinT);
  const double climb_J = 220.0 * kG * (50.0 + 0.006 * 500.0 * (cosT - 1.0)) / 0.85;  // through η = 0.85
  EXPECT_NEAR(ramp.pack_Wh - flat.pack_Wh, climb_J / 3600.0, 0.01);
}

TEST(VehicleRace, BadRouteCsvRowsNameFileLineFieldAndRange) {
  const auto dir = test::processTempDir("route_csv_bad");
  auto errorOf = [&](const std::string& name, const std::string& text) {
    const auto csv = dir / name;
    {
      std::ofstream out(csv);
      out << text;
    }
    return test::scenarioErrorOf([&] {
      loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"), {{"load.route", "{csv: " + csv.string() + ", segments: []}"}});
    });
  };
  const std::string grade = errorOf("grade.csv", "distance_m,grade_percent,speed_kmh\n0,0,27\n500,130,27\n1000,0,27\n");
  EXPECT_NE(grade.find("grade.csv:3:"), std::string::npos) << grade;
  EXPECT_NE(grade.find("grade_percent"), std::string::npos) << grade;
  EXPECT_NE(grade.find("[-100, 100] %"), std::string::npos) << grade;
  const std::string order = errorOf("order.csv", "distance_km,grade_percent,speed_kmh\n0,0,27\n1,0,27\n0.5,0,27\n");
  EXPECT_NE(order.find("order.csv:4:"), std::string::npos) << order;
  EXPECT_NE(order.find("increase strictly: 0.5 after 1 on line 3"), std::string::npos) << order;
  // A GPS log's repeated point (the vehicle stood): the message said "412 after the
  // previous row's", naming neither that row nor its distance.
  const std::string rep = errorOf("rep.csv", "distance_m,elevation_m,speed_kmh\n0,100,27\n412,104,27\n412,104,27\n1600,100,27\n");
  EXPECT_NE(rep.find("rep.csv:4:"), std::string::npos) << rep;
  EXPECT_NE(rep.find("412 after 412 on line 3 (a repeated point"), std::string::npos) << rep;
  const std::string head = errorOf("head.csv", "distance_km,grade_percent,sped_kmh\n0,0,27\n1,0,27\n");
  EXPECT_NE(head.find("head.csv:1:"), std::string::npos) << head;
  EXPECT_NE(head.find("speed_kmh"), std::string::npos) << head;
  const std::string wind = errorOf("wind.csv", "distance_km,grade_percent,speed_kmh,wind_kmh\n0,0,27,5\n1,0,27,5\n");
  EXPECT_NE(wind.find("wind_from_deg"), std::string::npos) << wind;
  const std::string num = errorOf("num.csv", "distance_km,grade_percent,speed_kmh\n0,0,27\n1,x,27\n");
  EXPECT_NE(num.find("num.csv:3:"), std::string::npos) << num;
  EXPECT_NE(num.find("not a finite number"), std::string::npos) << num;
}

TEST(VehicleRace, LapsOfARouteThatDoesNotCloseAreRefused) {
  // A GPS log of one lap (odd spacing, a descent) whose last altitude is 3 m above its
  // first: driven for 3 laps each lap climbed 3 m that no lap descended, m·g·h/η =
  // 150·9.80665·3/0.8 J = 1.53 Wh a lap more than the circuit costs (16 % of its
  // 9.5 Wh), and no word. Now refused, naming the laps key and the net climb; the same
  // log closed (last row at the first's height) loads, as does the open one driven once.
  const auto dir = test::processTempDir("route_csv_open");
  auto table = [&](const std::string& name, double lastElevation_m) {
    const auto csv = dir / name;
    std::ofstream out(csv);
    out << "distance_m,elevation_m,speed_kmh\n0,100,30\n37.4,100.2,30\n412,104,30\n731.7,99,25\n1400,"
        << lastElevation_m << ",30\n";
    return csv.string();
  };
  auto load = [&](const std::string& route) {
    return loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"), {{"load.route", route}});
  };
  const std::string open = table("open.csv", 103.0);
  const std::string e = test::scenarioErrorOf([&] { load("{csv: " + open + ", segments: [], laps: 3}"); });
  EXPECT_NE(e.find("load.route.laps"), std::string::npos) << e;
  EXPECT_NE(e.find("climb a net 3 m"), std::string::npos) << e;
  EXPECT_NE(e.find("9 m in all"), std::string::npos) << e;
  EXPECT_NO_THROW(load("{csv: " + open + ", segments: [], laps: 1}"));
  const Scenario closed = load("{csv: " + table("closed.csv", 100.0) + ", segments: [], laps: 3}");
  double rise_m = 0.0;  // the length is along the road: each segment climbs length · sin θ
  for (const RouteSegment& g : closed.vehicle.route.segments) rise_m += g.length_m * std::sin(std::atan(g.grade));
  EXPECT_NEAR(rise_m, 0.0, 1e-9);
  // Segments likewise: a climb with no descent, twice round, descends nowhere (250 m of
  // road at 2 %: 250·sin(atan 0.02) = 4.999 m).
  const std::string seg = test::scenarioErrorOf(
      [&] { load("{segments: [{length_m: 500, speed_kmh: 27}, {length_m: 250, grade_percent: 2, speed_kmh: 27}], laps: 2}"); });
  EXPECT_NE(seg.find("climb a net 4.999 m"), std::string::npos) << seg;
}

TEST(VehicleRace, WindByDirectionIsItsComponentAgainstTheHeading) {
  // 20 km/h from 60° on a road heading 0°: a headwind of 20·cos 60° = 10 km/h.
  const auto dir = test::processTempDir("route_csv_dir");
  const auto csv = dir / "dir.csv";
  {
    std::ofstream out(csv);
    out << "distance_km,grade_percent,speed_kmh,wind_kmh,wind_from_deg,heading_deg\n0,0,27,20,60,0\n1,0,27,20,60,180\n"
        << "2,0,27,0,0,0\n";
  }
  const Scenario s = loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"), {{"load.route", "{csv: " + csv.string() + ", segments: []}"}});
  EXPECT_NEAR(s.vehicle.route.segments[0].headwind_m_per_s * 3.6, 10.0, 1e-9);
  EXPECT_NEAR(s.vehicle.route.segments[1].headwind_m_per_s * 3.6, -10.0, 1e-9);  // the way back: a tailwind
}

TEST(VehicleRace, AnIrradianceTableGivesTheHandArrayIntegral) {
  // The eco car with a 0.5 m² array at 20 % through a 95 % MPPT under a measured day
  // (global horizontal, by the run's clock): 200 W/m² rising to 900 at 1200 s, falling
  // to 300 at 3000 s. Its energy is A·η·η_mppt·∫G dt from set-off to the finish, the
  // piecewise-linear integral worked here in closed form.
  const auto dir = test::processTempDir("irradiance_csv");
  const auto csv = dir / "sun.csv";
  {
    std::ofstream out(csv);
    out << "# a cloudless morning, then haze\ntime_s,ghi_W_per_m2\n0,200\n1200,900\n3000,300\n";
  }
  const Scenario plain = loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"), {{"run.solver", "fast"}});
  const Scenario s = loadScenarioFileWithOverrides(
      race("eco_marathon_12s_circuit"),
      {{"run.solver", "fast"},
       {"load.sun", "{array_area_m2: 0.5, efficiency: 0.2, mppt_efficiency: 0.95, start_solar_hour: 10, irradiance_csv: " +
                        csv.string() + "}"}});
  ASSERT_EQ(s.vehicle.array.table.at.size(), 3u);
  const RunResult a = runScenario(plain), r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  ASSERT_LT(v.time_s, 3000.0);
  // ∫ of a line from (t0, g0) to (t1, g1) over [a, b] inside it.
  auto line = [](double t0, double g0, double t1, double g1, double a, double b) {
    auto g = [&](double t) { return g0 + (g1 - g0) * (t - t0) / (t1 - t0); };
    return 0.5 * (g(a) + g(b)) * (b - a);
  };
  const double t0 = v.start_s, t1 = v.time_s;
  ASSERT_LT(t0, 1200.0);
  ASSERT_GT(t1, 1200.0);
  const double e_J = line(0, 200, 1200, 900, t0, 1200) + line(1200, 900, 3000, 300, 1200, t1);
  const double array_Wh = 0.5 * 0.2 * 0.95 * e_J / 3600.0;
  EXPECT_GT(array_Wh, 30.0);
  EXPECT_NEAR(v.array_Wh, array_Wh, 0.02 * array_Wh);
  EXPECT_NEAR(a.summary.vehicle.pack_Wh - v.pack_Wh, array_Wh, 0.02 * array_Wh);
}

TEST(VehicleRace, ARunTimeIrradianceTableEndsTheRunAtItsLastRow) {
  const auto dir = test::processTempDir("irradiance_end");
  const auto csv = dir / "short.csv";
  {
    std::ofstream out(csv);
    out << "time_s;poa_W_per_m2\n0;500,5\n600;500,5\n";  // semicolons, decimal commas
  }
  const Scenario s = loadScenarioFileWithOverrides(
      race("eco_marathon_12s_circuit"),
      {{"run.solver", "fast"}, {"expect", "{}"},
       {"load.sun", "{array_area_m2: 0.5, efficiency: 0.2, start_solar_hour: 10, irradiance_csv: " + csv.string() + "}"}});
  EXPECT_TRUE(s.vehicle.array.table.plane_of_array);
  EXPECT_DOUBLE_EQ(s.vehicle.array.table.irradiance_W_per_m2[0], 500.5);
  const RunResult r = runScenario(s);
  EXPECT_FALSE(r.summary.vehicle.finished);
  EXPECT_NEAR(r.summary.duration_s, 600.0, 0.2);
  EXPECT_DOUBLE_EQ(r.summary.vehicle.sun_table_end_s, 600.0);
  const std::string text = formatSummary(s, r);
  EXPECT_NE(text.find("when the irradiance table ended at 600 s"), std::string::npos) << text;
}

TEST(VehicleRace, BadIrradianceCsvRowsNameFileLineFieldAndRange) {
  const auto dir = test::processTempDir("irradiance_bad");
  auto errorOf = [&](const std::string& name, const std::string& text, const std::string& extra = "") {
    const auto csv = dir / name;
    {
      std::ofstream out(csv);
      out << text;
    }
    return test::scenarioErrorOf([&] {
      loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"),
                                    {{"load.sun", "{array_area_m2: 0.5, efficiency: 0.2, start_solar_hour: 10, " + extra +
                                                      "irradiance_csv: " + csv.string() + "}"}});
    });
  };
  const std::string high = errorOf("high.csv", "time_s,ghi_W_per_m2\n0,100\n60,2500\n");
  EXPECT_NE(high.find("high.csv:3:"), std::string::npos) << high;
  EXPECT_NE(high.find("ghi_W_per_m2"), std::string::npos) << high;
  EXPECT_NE(high.find("[0, 2000] W/m2"), std::string::npos) << high;
  const std::string order = errorOf("order.csv", "time_s,ghi_W_per_m2\n0,100\n60,200\n30,300\n");
  EXPECT_NE(order.find("order.csv:4:"), std::string::npos) << order;
  EXPECT_NE(order.find("increase strictly"), std::string::npos) << order;
  const std::string head = errorOf("head.csv", "time_s,gh_W_per_m2\n0,100\n60,200\n");
  EXPECT_NE(head.find("head.csv:1:"), std::string::npos) << head;
  EXPECT_NE(head.find("ghi_W_per_m2"), std::string::npos) << head;
  const std::string day = errorOf("day.csv", "solar_hour,ghi_W_per_m2\n0,0\n12,800\n18,0\n");
  EXPECT_NE(day.find("day.csv:4:"), std::string::npos) << day;
  EXPECT_NE(day.find("24 h"), std::string::npos) << day;
  const std::string both = errorOf("both.csv", "time_s,ghi_W_per_m2\n0,100\n60,200\n", "latitude_deg: 45, ");
  EXPECT_NE(both.find("latitude_deg"), std::string::npos) << both;
  EXPECT_NE(both.find("irradiance_csv"), std::string::npos) << both;
}

TEST(VehicleRace, AnEnergyPerLapDriverHoldsItsBudgetEveryLap) {
  // The eco car under a 14 Wh-a-lap rule (its 27 km/h costs 15.19 Wh): the driver picks
  // each lap's cruise speed from the road-load equation; the pack's own energy
  // quadrature over each lap (not the driver's plan) must come out at 14 Wh within 1 %,
  // the first lap from a standstill included.
  auto lapAt_Wh = [](double u) {  // the steady lap at u, by hand
    return ((force_N(220, 0.006, 1.2, 0.25, u, 0.0) * 1100.0 + force_N(220, 0.006, 1.2, 0.25, u, 0.03) * 250.0) / 0.85 +
            8.0 * 1600.0 / u) / 3600.0;
  };
  {
    const Scenario s = loadScenarioFileWithOverrides(
        race("eco_marathon_12s_circuit"), {{"run.solver", "fast"}, {"load.driver.lap_energy_Wh", "14"}, {"expect", "{}"}});
    const RunResult r = runScenario(s);
    const VehicleSummary& v = r.summary.vehicle;
    ASSERT_TRUE(v.finished);
    ASSERT_EQ(v.laps.size(), 10u);
    for (const LapRecord& l : v.laps) EXPECT_NEAR(l.pack_Wh, 14.0, 0.01 * 14.0) << "lap " << l.lap;
    // Each lap also pays for getting from its start speed to its cruise, so the speed
    // climbs lap by lap to the steady one, where (F_flat(u)·1100 m + F_up(u)·250 m)/0.85
    // + 8 W·1600 m/u = 14 Wh: 21.75 km/h by bisection here.
    double lo = 1.0, hi = kEcoV;  // the lap energy rises with u over this range
    for (int k = 0; k < 60; ++k) (lapAt_Wh(0.5 * (lo + hi)) < 14.0 ? lo : hi) = 0.5 * (lo + hi);
    const double u = 0.5 * (lo + hi);
    EXPECT_NEAR(u * 3.6, 21.75, 0.01);
    for (size_t i = 7; i < v.laps.size(); ++i) EXPECT_NEAR(1600.0 / v.laps[i].time_s, u, 0.005 * u) << "lap " << i + 1;
    EXPECT_LT(1600.0 / v.laps[0].time_s, 1600.0 / v.laps[1].time_s);
  }
  {
    // 12 Wh is below the cheapest lap there is (lifting 220 kg by 7.5 m costs 5.3 Wh a lap
    // through 0.85 with nothing regenerated): the driver drives the cheapest lap, its
    // energy the minimum of the hand lap energy over u.
    const Scenario s = loadScenarioFileWithOverrides(
        race("eco_marathon_12s_circuit"),
        {{"run.solver", "fast"}, {"load.driver.lap_energy_Wh", "12"}, {"load.route.laps", "3"}, {"expect", "{}"}});
    const RunResult r = runScenario(s);
    double least = 1e9;
    for (double u = 0.5; u < kEcoV; u += 0.001) least = std::min(least, lapAt_Wh(u));
    EXPECT_GT(least, 12.5);
    const VehicleSummary& v = r.summary.vehicle;
    ASSERT_EQ(v.laps.size(), 3u);
    for (size_t i = 1; i < v.laps.size(); ++i) EXPECT_NEAR(v.laps[i].pack_Wh, least, 0.01 * least) << "lap " << i + 1;
  }
}

TEST(VehicleRace, AnEfficiencyMapGivesTheHandLapBudget) {
  // The eco car with a map over wheel speed and torque (r 0.25 m) instead of its 0.85:
  // at 27 km/h (7/20 of the way from 20 to 40 km/h) the flat's 21.38 N is 5.35 N·m and
  // the climb's 86.07 N is 21.5 N·m; η by hand, bilinear between the four points around.
  const Scenario s = loadScenarioFileWithOverrides(
      race("eco_marathon_12s_circuit"),
      {{"run.solver", "fast"}, {"expect", "{}"}, {"run.duration_s", "3000"},
       {"load.vehicle.drivetrain_efficiency",
        "{wheel_radius_m: 0.25, speed_kmh: [0, 20, 40], torque_Nm: [0, 10, 30], "
        "efficiency: [[0.5, 0.6, 0.7], [0.6, 0.8, 0.85], [0.7, 0.9, 0.8]]}"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  const double fFlat = force_N(220, 0.006, 1.2, 0.25, kEcoV, 0.0), fUp = force_N(220, 0.006, 1.2, 0.25, kEcoV, 0.03);
  const double fv = (27.0 - 20.0) / 20.0;
  auto eta = [&](double torque) {  // between torque 10 and 30 (rows at 20 and 40 km/h), or 0 and 10
    if (torque < 10.0) {
      const double ft = torque / 10.0;
      return (1 - fv) * (0.6 + ft * 0.2) + fv * (0.7 + ft * 0.2);
    }
    const double ft = (torque - 10.0) / 20.0;
    return (1 - fv) * (0.8 + ft * 0.05) + fv * (0.9 - ft * 0.1);
  };
  const double etaFlat = eta(fFlat * 0.25), etaUp = eta(fUp * 0.25);
  EXPECT_NEAR(etaFlat, 0.7419, 1e-3);
  EXPECT_NEAR(etaUp, 0.8336, 1e-3);
  const double lap_Wh = (fFlat * 1100.0 / etaFlat + fUp * 250.0 / etaUp + 8.0 * 1600.0 / kEcoV) / 3600.0;
  for (size_t i = 1; i < v.laps.size(); ++i) EXPECT_NEAR(v.laps[i].pack_Wh, lap_Wh, 0.01 * lap_Wh) << "lap " << i + 1;
}

TEST(VehicleRace, BadEfficiencyMapsNameTheFieldAndRange) {
  auto errorOf = [&](const std::string& map) {
    return test::scenarioErrorOf([&] {
      loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"), {{"load.vehicle.drivetrain_efficiency", map}});
    });
  };
  const std::string cell = errorOf("{wheel_radius_m: 0.25, speed_kmh: [0, 20], torque_Nm: [0, 10], efficiency: [[0.5, 0.6], [0.7, 1.2]]}");
  EXPECT_NE(cell.find("efficiency[1][1]"), std::string::npos) << cell;
  EXPECT_NE(cell.find("(0, 1]"), std::string::npos) << cell;
  const std::string rows = errorOf("{wheel_radius_m: 0.25, speed_kmh: [0, 20, 40], torque_Nm: [0, 10], efficiency: [[0.5, 0.6], [0.7, 0.8]]}");
  EXPECT_NE(rows.find("3 rows"), std::string::npos) << rows;
  const std::string axis = errorOf("{wheel_radius_m: 0.25, speed_kmh: [5, 20], torque_Nm: [0, 10], efficiency: [[0.5, 0.6], [0.7, 0.8]]}");
  EXPECT_NE(axis.find("speed_kmh"), std::string::npos) << axis;
  EXPECT_NE(axis.find("start at 0"), std::string::npos) << axis;
  const std::string order = errorOf("{wheel_radius_m: 0.25, speed_kmh: [0, 20], torque_Nm: [0, 10, 10], efficiency: [[0.5, 0.6, 0.6], [0.7, 0.8, 0.8]]}");
  EXPECT_NE(order.find("increase strictly"), std::string::npos) << order;
}

// A run that ends by its duration before the route's time limit decides nothing about
// the limit: the line says how long the run drove, how far from the limit and the finish
// it was, not "not met".
TEST(VehicleRace, ARunEndedBeforeTheTimeLimitDoesNotJudgeIt) {
  const Scenario s = loadScenarioFileWithOverrides(race("eco_marathon_12s_circuit"), {{"run.duration_s", "300"}});
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_FALSE(v.finished);
  ASSERT_FALSE(r.summary.tripped);
  const double driven_s = v.time_s - v.start_s;
  EXPECT_NEAR(driven_s, 300.0 - v.start_s, 0.02);
  char expected[200];
  std::snprintf(expected, sizeof expected,
                "time limit      2400 s: not reached: the run ended %.1f s after setting off, %.1f s before the limit, "
                "%.3f km of the route left",
                driven_s, 2400.0 - driven_s, (16000.0 - v.distance_m) / 1000.0);
  const std::string text = formatSummary(s, r);
  EXPECT_NE(text.find(expected), std::string::npos) << text;
  EXPECT_EQ(text.find("not met"), std::string::npos) << text;
}

TEST(VehicleRace, AFoldBackOnASaggingPackSettlesWhereLimitAndPackMeet) {
  // A 13s4p scooter pack climbing 8 % with a fold-back of 1 V: 30 A sag the pack by
  // about 4 V, so the controller's limit and the pack meet inside the window. A limit
  // set at the voltage of the tick before rang (full power one tick, the aux alone the
  // next, the car crawling up the hill at 50 Hz while every 1 s sample showed 0.19 A):
  // now every tick inside a fold-back episode sits on the controller's line
  // I = 30·(V - 44)/1 at the recorded pack voltage, and the current moves smoothly.
  // Recorded every tick (the vehicle's limit at sample k is the one of the tick that
  // ended at t_k; the current is that of the tick starting there).
  const Scenario s = test::scenarioFromYaml(
      "name: foldback\n"
      "pack: {series: 13, parallel: 4, initial_soc: 0.5, initial_temp_C: 25, cell: {preset: ncr18650_3p1Ah}}\n"
      "ambient: {temp_C: 25}\n"
      "bms: {protections: {overcurrent_discharge: {threshold_A: 40}, overcurrent_charge: {threshold_A: 12}}}\n"
      "load:\n"
      "  vehicle: {mass_kg: 110, rolling_coefficient: 0.012, drag_area_m2: 0.55, drivetrain_efficiency: 0.82,\n"
      "            max_drive_power_W: 1500, aux_power_W: 8, max_current_A: 30, cutoff_start_V: 45, cutoff_end_V: 44}\n"
      "  route: {segments: [{length_m: 600, speed_kmh: 20, grade_percent: 8}]}\n"
      "  driver: {accel_m_per_s2: 1.0, response_s: 2}\n"
      "run: {solver: fast}\n"
      "output: {interval_s: 0.01}\n");
  const RunResult r = runScenario(s);
  const VehicleSummary& v = r.summary.vehicle;
  ASSERT_TRUE(v.finished);
  ASSERT_TRUE(v.limited);
  EXPECT_EQ(v.limit_detail.rfind("low_voltage_foldback", 0), 0u) << v.limit_detail;
  // The event's figures are the controller's point: the current it allowed at that voltage.
  const size_t at = v.limit_detail.find(" W short (pack ");
  ASSERT_NE(at, std::string::npos) << v.limit_detail;
  double packV = 0.0, allowedA = 0.0;
  ASSERT_EQ(std::sscanf(v.limit_detail.c_str() + at, " W short (pack %lf V, the controller allowed %lf A)", &packV, &allowedA), 2);
  EXPECT_NEAR(allowedA, 30.0 * (packV - 44.0), 0.01 + 30.0 * 0.005);  // both printed to 0.01
  const Recording& rec = r.rec;
  const auto fold = static_cast<uint8_t>(DriveLimit::VoltageFoldback);
  int inside = 0;
  for (size_t k = 1; k + 1 < rec.samples(); ++k) {
    if (rec.vehicle_limit[k] != fold || rec.vehicle_limit[k + 1] != fold) continue;
    ++inside;
    const double i = rec.pack_current_A[k], u = rec.pack_voltage_V[k];
    EXPECT_NEAR(i, 30.0 * (u - 44.0), 1e-6) << rec.time_s[k];
    EXPECT_GT(i, 5.0) << rec.time_s[k];                                        // never the aux alone
    EXPECT_LT(std::fabs(i - rec.pack_current_A[k - 1]), 0.2) << rec.time_s[k];  // no ringing
  }
  EXPECT_GT(inside, 1000);  // the climb is mostly folded back (> 10 s of ticks)
  // The climb's energy: the wheels did at least the lift, the rolling and the speed the
  // car reached, η·(pack - aux) of it (aero and the last tick's speed-up on top).
  const size_t end = rec.samples() - 1;
  const double lift_J = 110.0 * kG * 0.08 / std::sqrt(1.0 + 0.0064) * 600.0;
  const double roll_J = 110.0 * kG * 0.012 / std::sqrt(1.0 + 0.0064) * 600.0;
  const double vEnd = rec.vehicle_speed_m_per_s[end];
  const double wheel_J = 0.82 * (r.summary.energy_delivered_Wh * 3600.0 - 8.0 * (v.time_s - v.start_s));
  EXPECT_GT(wheel_J, lift_J + roll_J + 0.5 * 110.0 * vEnd * vEnd);
  EXPECT_LT(wheel_J, 1.05 * (lift_J + roll_J + 0.5 * 110.0 * (20.0 / 3.6) * (20.0 / 3.6)) + 0.5 * 1.2 * 0.55 * 31.0 * 600.0);
}

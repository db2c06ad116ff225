// The vehicle, route and sun models against hand calculations (docs/vehicle.md).
#include <gtest/gtest.h>

#include <cmath>

#include "models/vehicle/clear_sky.hpp"
#include "models/vehicle/lap_energy.hpp"
#include "models/vehicle/road_load.hpp"
#include "models/vehicle/route.hpp"
#include "models/vehicle/vehicle.hpp"

using namespace packsim;

namespace {
VehicleParams car() {
  VehicleParams p;
  p.mass_kg = 100.0;
  p.rolling_coefficient = 0.01;
  p.drag_area_m2 = 0.5;
  p.air_density_kg_per_m3 = 1.2;
  p.drivetrain_efficiency = 0.8;
  p.max_drive_power_W = 1.0e6;
  return p;
}
Route flat(double speed, double length_m = 1000.0, int laps = 1) {
  Route r;
  r.segments = {RouteSegment{length_m, 0.0, speed}};
  r.laps = laps;
  return r;
}
}  // namespace

TEST(RoadLoad, ResistanceByHand) {
  // 100 kg · 9.80665 · 0.01 = 9.80665 N rolling; ½ · 1.2 · 0.5 · 10² = 30 N drag.
  EXPECT_NEAR(resistanceForce_N(car(), 10.0, 0.0), 39.80665, 1e-9);
  // 10 % grade: cos θ = 1/√1.01, sin θ = 0.1/√1.01.
  const double c = 1.0 / std::sqrt(1.01);
  EXPECT_NEAR(resistanceForce_N(car(), 10.0, 0.1), 9.80665 * c + 30.0 + 980.665 * 0.1 * c, 1e-9);
}

TEST(RoadLoad, AccelerationInvertsWheelPower) {
  for (double v : {0.0, 3.0, 15.0})
    for (double a : {-0.5, 0.0, 0.7})
      for (double g : {-0.05, 0.0, 0.08}) {
        if (v + 0.5 * a * 0.1 < 0.0) continue;
        const double p = wheelPower_W(car(), v, g, a, 0.1);
        // At rest with no power both a = 0 and a = -F/m solve it: downhill the car rolls.
        if (v == 0.0 && a <= 0.0) continue;
        EXPECT_NEAR(accelerationFor(car(), v, g, p, 0.1), a, 1e-9) << v << " " << a << " " << g;
      }
}

TEST(RoadLoad, FoldbackIsLinearBetweenItsVoltages) {
  VehicleParams p = car();
  EXPECT_TRUE(std::isinf(allowedCurrent_A(p, 40.0)));
  p.max_current_A = 30.0;
  p.cutoff_start_V = 44.0;
  p.cutoff_end_V = 40.0;
  EXPECT_DOUBLE_EQ(allowedCurrent_A(p, 48.0), 30.0);
  EXPECT_DOUBLE_EQ(allowedCurrent_A(p, 43.0), 30.0 * 0.75);
  EXPECT_DOUBLE_EQ(allowedCurrent_A(p, 39.0), 0.0);
}

TEST(Route, LapsSegmentsAndBrakingLookAhead) {
  Route r;
  r.segments = {RouteSegment{100.0, 0.0, 20.0}, RouteSegment{100.0, 0.02, 10.0}};
  r.laps = 3;
  EXPECT_DOUBLE_EQ(r.total_m(), 600.0);
  EXPECT_EQ(r.segmentAt(150.0), 1);
  EXPECT_EQ(r.segmentAt(250.0), 0);
  EXPECT_EQ(r.lapAt(250.0), 1);
  EXPECT_EQ(r.lapAt(600.0), 3);
  // Braking at 1 m/s² for the 10 m/s segment at 100 m: √(10² + 2·1·100) at 0 m.
  EXPECT_NEAR(r.targetSpeed_m_per_s(0.0, 1.0), std::sqrt(300.0), 1e-12);
  EXPECT_NEAR(r.targetSpeed_m_per_s(50.0, 1.0), std::sqrt(200.0), 1e-12);
  EXPECT_DOUBLE_EQ(r.targetSpeed_m_per_s(150.0, 1.0), 10.0);
  // Leaving the slow segment, the next lap's fast one: its own 20 m/s (nothing slower ahead
  // within reach until the next slow segment at 300 m: √(100 + 2·(300 - 210)) = 16.7).
  EXPECT_NEAR(r.targetSpeed_m_per_s(210.0, 1.0), std::sqrt(100.0 + 180.0), 1e-12);
}

TEST(Vehicle, AcceleratesAtItsBoundThenCruisesAtTheTarget) {
  DriverParams d;
  d.accel_m_per_s2 = 1.0;
  d.response_s = 2.0;
  Vehicle v(car(), flat(20.0), d);
  const double dt = 0.01;
  for (int k = 0; k < 500; ++k) {  // 5 s at 1 m/s² (v < 18 m/s: the bound holds)
    const VehiclePlan p = v.plan(dt, {50.0, 0.0}, 0.0, true);
    v.advance(p, p.net_W, dt);
  }
  EXPECT_NEAR(v.speed_m_per_s(), 5.0, 1e-9);
  EXPECT_NEAR(v.distance_m(), 12.5, 1e-9);
}

TEST(Vehicle, CruisePackPowerIsTheRoadLoadOverEfficiencyPlusAux) {
  VehicleParams p = car();
  p.aux_power_W = 15.0;
  Vehicle v(p, flat(10.0, 5000.0), DriverParams{});
  VehiclePlan pl;
  for (int k = 0; k < 6000; ++k) {  // 60 s: settled at 10 m/s
    pl = v.plan(0.01, {50.0, 0.0}, 0.0, true);
    v.advance(pl, pl.net_W, 0.01);
  }
  EXPECT_NEAR(v.speed_m_per_s(), 10.0, 1e-6);
  EXPECT_NEAR(pl.net_W, 39.80665 * 10.0 / 0.8 + 15.0, 1e-3);
}

TEST(Vehicle, PowerCapGivesTheKineticEnergyOfItsWork) {
  // No resistance: ½·m·v² = η·P·t exactly (the tick's work is F·ds).
  VehicleParams p = car();
  p.rolling_coefficient = 0.0;
  p.drag_area_m2 = 0.0;
  DriverParams d;
  d.accel_m_per_s2 = 100.0;
  d.power_cap_W = 500.0;
  d.response_s = 0.01;  // wants 100 m/s² from the first tick: the cap binds throughout
  Vehicle v(p, flat(50.0, 1e5), d);
  for (int k = 0; k < 1000; ++k) {  // 10 s
    const VehiclePlan pl = v.plan(0.01, {50.0, 0.0}, 0.0, true);
    ASSERT_EQ(pl.limit, DriveLimit::DriverCap);
    v.advance(pl, pl.net_W, 0.01);
  }
  EXPECT_NEAR(v.speed_m_per_s(), std::sqrt(2.0 * 0.8 * 500.0 * 10.0 / 100.0), 1e-9);
}

TEST(Vehicle, ControllerLimitsThePackCurrentAndAShortfallSlowsIt) {
  VehicleParams p = car();
  p.max_current_A = 10.0;
  p.aux_power_W = 20.0;
  Vehicle v(p, flat(20.0), DriverParams{});
  VehiclePlan pl;
  for (int k = 0; k < 500; ++k) {  // 5 s at 1 m/s² on a pack without limits: 5 m/s, ~730 W
    pl = v.plan(0.01, {48.0, 0.0}, 0.0, false);
    v.advance(pl, pl.net_W, 0.01);
  }
  // At 48 V the pack may give 480 W: 460 W to the drive, 20 W to the aux.
  pl = v.plan(0.01, {48.0, 0.0}, 0.0, true);
  EXPECT_EQ(pl.limit, DriveLimit::ControllerCurrent);
  EXPECT_NEAR(pl.net_W, 480.0, 1e-9);
  // The reference vehicle is not limited by the pack.
  EXPECT_EQ(v.plan(0.01, {48.0, 0.0}, 0.0, false).limit, DriveLimit::None);
  // Cruising at 10 m/s, the pack gives nothing: the vehicle coasts at -F/m.
  Vehicle c(car(), flat(10.0), DriverParams{});
  for (int k = 0; k < 3000; ++k) {
    pl = c.plan(0.01, {50.0, 0.0}, 0.0, true);
    c.advance(pl, pl.net_W, 0.01);
  }
  const double v0 = c.speed_m_per_s();
  pl = c.plan(0.01, {50.0, 0.0}, 0.0, true);
  EXPECT_EQ(c.advance(pl, 0.0, 0.01), DriveLimit::PackShortfall);
  EXPECT_NEAR((c.speed_m_per_s() - v0) / 0.01, -resistanceForce_N(car(), v0, 0.0) / 100.0, 1e-9);
}

TEST(ClearSky, NoonIrradianceByHand) {
  // Equinox (day 80) on the equator at noon: the sun overhead, AM 1:
  // 1.1 · 1353 · 0.7 = 1041.8 W/m² (declination -0.40°: cos z = 0.99998).
  EXPECT_NEAR(clearSkyIrradiance_W_per_m2({0.0, 80}, 12.0), 1041.78, 0.01);
  // 45° N at midsummer noon: z = 45° - 23.45°, AM 1.0752: 951.73 W/m².
  EXPECT_NEAR(clearSkyIrradiance_W_per_m2({45.0, 172}, 12.0), 951.73, 0.01);
  // Night, and sunrise at 06:00 solar time on the equator at the equinox.
  EXPECT_EQ(clearSkyIrradiance_W_per_m2({45.0, 172}, 0.5), 0.0);
  EXPECT_EQ(clearSkyIrradiance_W_per_m2({0.0, 80}, 5.9), 0.0);
  EXPECT_GT(clearSkyIrradiance_W_per_m2({0.0, 80}, 6.2), 0.0);
  // A 4 m² array at 22 % through a 97 % MPPT, started at 11:00, one hour later.
  SolarArray a{4.0, 0.22, 0.97, {0.0, 80}, 11.0};
  EXPECT_NEAR(a.power_W(3600.0), 4.0 * 0.22 * 0.97 * 1041.78, 0.01);
}

TEST(ClearSky, AnIrradianceTableIsLinearBetweenItsRows) {
  // Time of day: 0 W/m² to 06:00, 800 at 12:00, 0 from 18:00; the same day repeated.
  IrradianceTable day;
  day.clock = IrradianceTable::Clock::TimeOfDay;
  day.at = {0.0, 6.0, 12.0, 18.0, 24.0};
  day.irradiance_W_per_m2 = {0.0, 0.0, 800.0, 0.0, 0.0};
  EXPECT_DOUBLE_EQ(day.value_W_per_m2(0.0, 9.0), 400.0);        // halfway up
  EXPECT_DOUBLE_EQ(day.value_W_per_m2(0.0, 24.0 + 15.0), 400.0);  // day 2, 15:00
  EXPECT_DOUBLE_EQ(day.value_W_per_m2(0.0, 20.0), 0.0);
  EXPECT_TRUE(std::isinf(day.end_s()));
  // A 2 m² array at 20 % through a 95 % MPPT, the table by the run's clock.
  SolarArray a{2.0, 0.2, 0.95, {}, 10.0};
  a.table.at = {0.0, 100.0, 300.0};
  a.table.irradiance_W_per_m2 = {100.0, 500.0, 300.0};
  EXPECT_DOUBLE_EQ(a.power_W(50.0), 2.0 * 0.2 * 0.95 * 300.0);
  EXPECT_DOUBLE_EQ(a.power_W(200.0), 2.0 * 0.2 * 0.95 * 400.0);
  EXPECT_DOUBLE_EQ(a.table.end_s(), 300.0);
}

TEST(Vehicle, StopsAtTheLineWaitsAndSetsOff) {
  // 20 m/s on a 5 km road with a 60 s stop at 2 km: from v²/2d = b (200 m before the
  // line at b = 1 m/s²) it brakes at a constant v²/2d and stands at the line; it waits
  // the stop's duration and sets off again; the aux stays on while it waits.
  VehicleParams p = car();
  p.aux_power_W = 12.0;
  Route r = flat(20.0, 5000.0);
  r.stops = {RouteStop{2000.0, 60.0, 0.0, -1}};
  DriverParams d;
  d.brake_m_per_s2 = 1.0;
  Vehicle v(p, r, d);
  const double dt = 0.1;
  double t = 0.0, arrived = -1.0, departed = -1.0, arrivedAt_m = -1.0, peakBrake = 0.0;
  for (int k = 0; k < 4000 && departed < 0.0; ++k, t += dt) {
    const StopEvent e = v.serveStops(t);
    if (e == StopEvent::Arrived) {
      arrived = t;
      arrivedAt_m = v.distance_m();
    }
    if (e == StopEvent::Departed) departed = t;
    const VehiclePlan pl = v.plan(dt, {50.0, 0.0}, 0.0, true);
    if (v.parked()) EXPECT_NEAR(pl.net_W, 12.0, 1e-12);
    if (v.distance_m() > 1500.0) peakBrake = std::max(peakBrake, -pl.accel_m_per_s2);
    v.advance(pl, pl.net_W, dt);
  }
  ASSERT_GT(arrived, 0.0);
  EXPECT_NEAR(arrivedAt_m, 2000.0, 0.01);
  EXPECT_LE(peakBrake, 1.0 + 0.02);  // never harder than b (to the rounding of the first tick)
  EXPECT_NEAR(departed - arrived, 60.0, dt + 1e-9);
  // Back to the target afterwards.
  for (int k = 0; k < 600; ++k) {
    const VehiclePlan pl = v.plan(dt, {50.0, 0.0}, 0.0, true);
    v.advance(pl, pl.net_W, dt);
  }
  EXPECT_NEAR(v.speed_m_per_s(), 20.0, 1e-3);
}

TEST(Vehicle, AStageStartWaitsForItsTime) {
  // A stop at 0 m until t = 100 s (stage 1's start time): standing, nothing drawn
  // between stages, it sets off at the first tick at or after 100 s.
  VehicleParams p = car();
  p.aux_power_W = 12.0;
  Route r = flat(10.0);
  r.stops = {RouteStop{0.0, 0.0, 100.0, 0}};
  Vehicle v(p, r, DriverParams{});
  double t = 0.0, departed = -1.0;
  for (int k = 0; k < 2000 && departed < 0.0; ++k, t += 0.5) {
    if (v.serveStops(t) == StopEvent::Departed) departed = t;
    const VehiclePlan pl = v.plan(0.5, {50.0, 0.0}, 30.0, true);
    if (v.parked()) {
      EXPECT_EQ(pl.net_W, -30.0);  // the array charges the pack; no aux between stages
      EXPECT_EQ(v.distance_m(), 0.0);
    }
    v.advance(pl, pl.net_W, 0.5);
  }
  EXPECT_EQ(departed, 100.0);
}

TEST(RoadLoad, AHeadwindRaisesTheAeroPowerByTheSquareOfTheAirSpeed) {
  // At 10 m/s against 5 m/s of headwind the air passes at 15 m/s: the aerodynamic force
  // is ½·1.2·0.5·15² = 67.5 N, (15/10)² times the 30 N of still air; a 15 m/s tailwind
  // pushes: ½·1.2·0.5·(10 − 15)·|10 − 15| = −7.5 N.
  const double roll = 9.80665;
  EXPECT_NEAR(resistanceForce_N(car(), 10.0, 0.0, 5.0) - roll, 30.0 * (15.0 / 10.0) * (15.0 / 10.0), 1e-9);
  EXPECT_NEAR(resistanceForce_N(car(), 10.0, 0.0, -15.0) - roll, -7.5, 1e-9);
  // Cruising at 10 m/s into the wind: pack power (roll + 67.5 N)·10 m/s / η.
  Route r = flat(10.0, 5000.0);
  r.segments[0].headwind_m_per_s = 5.0;
  Vehicle v(car(), r, DriverParams{});
  VehiclePlan pl;
  for (int k = 0; k < 6000; ++k) {
    pl = v.plan(0.01, {50.0, 0.0}, 0.0, true);
    v.advance(pl, pl.net_W, 0.01);
  }
  EXPECT_NEAR(v.speed_m_per_s(), 10.0, 1e-6);
  EXPECT_NEAR(pl.net_W, (roll + 67.5) * 10.0 / 0.8, 1e-3);
}

TEST(LapEnergy, FlatSteadyLapSpeedByHand) {
  // A flat 1 km lap entered at the cruise speed, no auxiliaries: E = L·(m·g·C_rr + ½·ρ·CdA·u²)/η,
  // so u = √((E·η/L − m·g·C_rr)/(½·ρ·CdA)). 100 kg, C_rr 0.01, CdA 0.5, η 0.8; E = 10 Wh.
  const VehicleParams p = car();
  const Route r = flat(20.0);
  const double e_J = 36000.0;
  const double u = std::sqrt((e_J * 0.8 / 1000.0 - 100.0 * 9.80665 * 0.01) / (0.5 * 1.2 * 0.5));
  EXPECT_NEAR(u, 7.9568, 1e-3);  // (28.8 − 9.807 N)/0.3
  EXPECT_NEAR(lapSpeedFor(p, r, e_J, u, 20.0), u, 1e-6);
  EXPECT_NEAR(lapEnergy_J(p, r, u, u), e_J, 1e-6);
  // From a standstill the lap also pays ½·m·u²/η: slower.
  EXPECT_LT(lapSpeedFor(p, r, e_J, 0.0, 20.0), u - 0.1);
  // A budget above the route's own speed: the route's speed; below the cheapest: the cheapest.
  EXPECT_DOUBLE_EQ(lapSpeedFor(p, r, 1.0e7, u, 20.0), 20.0);
  VehicleParams aux = p;
  aux.aux_power_W = 50.0;  // E(u) then has a minimum where the auxiliaries' L/u meets the drag's u²
  const double cheapest = lapSpeedFor(aux, r, 1.0, 5.0, 20.0);
  // dE/du = 0: ρ·CdA·u·L/η = P_aux·L/u² (from the steady lap) -> u³ = P_aux·η/(ρ·CdA).
  EXPECT_NEAR(cheapest, std::cbrt(50.0 * 0.8 / (1.2 * 0.5)), 0.1 + 20.0 / 200);
}

TEST(DrivetrainMap, BilinearBetweenItsPointsAndHeldPastItsEdges) {
  DrivetrainMap m;
  m.wheel_radius_m = 0.25;
  m.speed_m_per_s = {0.0, 10.0, 20.0};
  m.torque_Nm = {0.0, 10.0, 30.0};
  m.efficiency = {0.5, 0.6, 0.7, /**/ 0.6, 0.8, 0.85, /**/ 0.7, 0.9, 0.8};
  EXPECT_DOUBLE_EQ(m.at(10.0, 10.0), 0.8);  // a grid point
  // v 15 (halfway 10..20), T 20 (halfway 10..30): the mean of 0.8, 0.85, 0.9, 0.8.
  EXPECT_NEAR(m.at(15.0, 20.0), 0.8375, 1e-12);
  // v 12.5 (a quarter), T 5 (half): (0.75·(0.6+0.8)/2 + 0.25·(0.7+0.9)/2).
  EXPECT_NEAR(m.at(12.5, 5.0), 0.75 * 0.7 + 0.25 * 0.8, 1e-12);
  EXPECT_DOUBLE_EQ(m.at(40.0, 100.0), 0.8);  // past both edges: the corner
  EXPECT_DOUBLE_EQ(m.at(40.0, 10.0), 0.9);
  // Cruise at 15 m/s on the flat: the torque is F_res·r, and the pack gives F_res·v/η(v, F_res·r).
  VehicleParams p = car();
  p.efficiency_map = m;
  const double f = 100.0 * 9.80665 * 0.01 + 0.5 * 1.2 * 0.5 * 15.0 * 15.0;  // 77.31 N: 19.33 N·m
  const double ft = (f * 0.25 - 10.0) / 20.0;
  const double eta = 0.5 * ((0.8 + ft * 0.05) + (0.9 - ft * 0.1));
  EXPECT_NEAR(drivetrainEfficiency(p, 15.0, f), eta, 1e-12);
  EXPECT_NEAR(drivetrainEfficiency(p, 15.0, -f), eta, 1e-12);  // braking: the same map
  Vehicle v(p, flat(15.0, 100000.0), DriverParams{});
  for (int k = 0; k < 600; ++k) {
    const VehiclePlan step = v.plan(0.1, {0.0, 0.0}, 0.0, false);
    v.advance(step, step.net_W, 0.1);
  }
  ASSERT_NEAR(v.speed_m_per_s(), 15.0, 1e-6);
  const VehiclePlan pl = v.plan(0.1, {0.0, 0.0}, 0.0, false);
  EXPECT_NEAR(pl.drive_W, f * 15.0 / eta, 1e-3 * f * 15.0 / eta);
}

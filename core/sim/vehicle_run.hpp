// The vehicle in front of the pack during a run (docs/vehicle.md). At every BMS tick t_k
// it first moves the vehicle over the tick that just ended with the pack power that
// actually flowed (the pack's load-energy quadrature over the tick: a trip, a blocked
// FET or a pack that cannot give the power all show there), then plans the next tick
// on the pack's EMF and resistance at t_k, and hands the loop the pack power to
// hold until t_k+1 (the plant solves V·I = P for it). A reference vehicle -- the same
// driver on a pack that never limits it -- runs beside it; the time lost to the pack
// is the difference of the two.
#pragma once
#include <string>

#include "core/scenario/vehicle_config.hpp"
#include "core/sim/vehicle_summary.hpp"

namespace packsim {

class RunTracker;

class VehicleRun {
 public:
  // fullCell_V: bms.charge_full_cell_V (0: none) -- with it the array stops charging the
  // pack once the BMS reads it on the highest module, until the vehicle next sets off.
  VehicleRun(const VehicleConfig& c, double tick_s, double fullCell_V);

  // At t_k: loadEnergy_J, the pack's energy out so far; pack, its EMF and resistance at
  // t_k (the controller's limit settles on them); ready, the BMS was in its normal state at the
  // last tick (the dashboard's ready light: the driver sets off at the first one);
  // maxCell_V: the highest cell (module) voltage the BMS reports.
  // Returns the pack power for [t_k, t_k+1) [W].
  double tick(double t_s, double loadEnergy_J, const PackSource& pack, bool ready, double maxCell_V, RunTracker& tracker);
  // The route is complete, or the vehicle stood still for standstill_end_s.
  // Or the irradiance table (sun.irradiance_csv by run time) ended.
  bool done() const { return car_.finished() || stood_ || sunEnded_; }
  std::string endReason() const;
  const VehicleSample& sample() const { return sample_; }
  // The loop recorded the sample at t: the next sample's array powers are the means
  // from here (VehicleSample::array_W).
  void recorded(double t_s);
  VehicleSummary summary(double end_s) const;

 private:
  void account(double t0, double dt, double e0_J, double e1_J, double s0, double s1, double a0_J, double a1_J);
  void stageEvent(StopEvent ev, double t, double e_J, RunTracker& tracker);
  std::string clock(double t_s) const;

  const VehicleConfig cfg_;
  const double dt_;
  const double fullCell_V_;
  bool full_ = false;                    // the BMS read the full voltage: the array charges no more
  Vehicle car_, ref_;
  VehiclePlan plan_, refPlan_;
  bool first_ = true;
  bool started_ = false;
  double energy_J_ = 0.0;   // load quadrature at the last tick
  double array_J_ = 0.0;    // array energy taken into the bus so far
  double availJ_ = 0.0;     // array energy the MPPT had so far (taken or not)
  double availPlan_W_ = 0.0;  // the MPPT's power over the tick planned last
  double recT_s_ = 0.0, recJ_ = 0.0, recAvailJ_ = 0.0;  // at the last recorded sample
  double still_s_ = 0.0;
  bool stood_ = false;
  bool sunEnded_ = false;
  double finish_s_ = -1.0, refFinish_s_ = -1.0;
  double lapStart_s_ = 0.0, lapStartE_J_ = 0.0, lapStartA_J_ = 0.0;
  std::vector<double> refLapEnd_s_;
  double finishE_J_ = 0.0, finishA_J_ = 0.0;  // at the finish line (interpolated)
  // the open stage (or the stop after it): energy, array energy and distance at its start
  double stageE_J_ = 0.0, stageA_J_ = 0.0, stageS_m_ = 0.0, parkE_J_ = 0.0, parkA_J_ = 0.0, parkT_s_ = 0.0;
  bool stageOpen_ = false, parkOpen_ = false;
  VehicleSummary sum_;
  VehicleSample sample_;
};

}  // namespace packsim

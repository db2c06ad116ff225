// A drivetrain efficiency map over wheel speed and wheel torque (the motor maker's
// efficiency map taken to the wheel: motor, controller and gearing together), read
// between its points by bilinear interpolation (docs/vehicle.md, "Drivetrain
// efficiency map"). The torque is |F_wheel|·r_wheel both ways (driving and
// regenerating use the same map); past the table's last speed or torque the edge
// value holds.
#pragma once
#include <vector>

namespace packsim {

struct DrivetrainMap {
  double wheel_radius_m = 0.0;
  std::vector<double> speed_m_per_s;  // from 0, strictly increasing
  std::vector<double> torque_Nm;      // from 0, strictly increasing
  std::vector<double> efficiency;     // row-major: efficiency[i * torque_Nm.size() + j] at speed i, torque j

  bool empty() const { return speed_m_per_s.empty(); }
  double at(double speed_m_per_s, double torque_Nm) const;
};

}  // namespace packsim

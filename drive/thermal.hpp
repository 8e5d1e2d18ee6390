// Winding temperature and I²t energy (drive-core.md §10.7). Forward Euler, one call per 1 ms step.
#pragma once

#include "drive/plant_config.hpp"

namespace mcemu::core {

class Thermal {
 public:
  explicit Thermal(const PlantParams& params) : params_(params) {}

  // Power on: T = T_amb + R_th·P_idle (warm electronics), E = 0.
  void reset(double ambient_c);
  // i = per-unit current |6078h| / 1000.
  void step(double i, double ambient_c);

  double temperature() const { return t_; }
  double energy() const { return e_; }
  // E_max = (1 − i_c²)·2 s with i_c = torque_cont / torque_peak
  double energy_max() const;
  void set_energy(double e) { e_ = e; }

 private:
  const PlantParams& params_;
  double t_ = 25;
  double e_ = 0;
};

}  // namespace mcemu::core

#include "plumetrace/agent/sensor_models.hpp"

#include <algorithm>
#include <cmath>

#include "plumetrace/core/math.hpp"

namespace plumetrace {

double FirstOrderSensor::gain(double tau, double dt, double& cached_dt, double& cached) const {
  if (dt != cached_dt) {
    cached_dt = dt;
    cached = tau > 0.0 ? -math::expm1(-dt / tau) : 1.0;
  }
  return cached;
}

double FirstOrderSensor::read(double c, double dt) {
  const double g = c > state_ ? gain(params_.tau_rise, dt, rise_dt_, rise_gain_)
                              : gain(params_.tau_decay, dt, decay_dt_, decay_gain_);
  state_ += (c - state_) * g;
  // why: no draw when there is no noise, so a noiseless sensor's stream stays untouched
  const double noisy = params_.noise > 0.0 ? state_ + params_.noise * rng_.normal() : state_;
  return std::max(0.0, noisy);
}

SensorModelRegistry& sensor_model_registry() {
  // in the order of SensorModel
  static SensorModelRegistry registry = [] {
    SensorModelRegistry r;
    r.add<IdealSensor, IdealSensorParams>("ideal");
    r.add<FirstOrderSensor, FirstOrderSensorParams>("first-order");
    return r;
  }();
  return registry;
}

}  // namespace plumetrace

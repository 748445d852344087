#pragma once

#include <cstddef>
#include <memory>

#include "plumetrace/core/config.hpp"
#include "plumetrace/core/registry.hpp"
#include "plumetrace/core/rng.hpp"

namespace plumetrace {

/// An odor sensor's response: turns the true concentration at the sensor, step by step, into its
/// reading (docs/agents.md, "Sensor models"). One per robot, with the robot's own random stream
/// (Stream::kOdorSensor).
class OdorSensorModel {
 public:
  virtual ~OdorSensorModel() = default;
  /// True when the reading is the concentration itself, with no state and no noise: then a
  /// controller that reads only the binary odor gets it from the threshold test alone, which
  /// stops summing filaments once the threshold is reached.
  virtual bool ideal() const { return false; }
  /// Starts the sensor at release in concentration `c` (a sensor that has settled there).
  virtual void reset(double c) = 0;
  /// The reading after a step of dt (s) at whose end the true concentration is `c`.
  virtual double read(double c, double dt) = 0;
};

/// The paper's sensor: the reading is the concentration, with no delay and no noise.
struct IdealSensorParams {
  /// No keys.
  template <class V>
  void fields(V&) {}
};

/// The ideal sensor.
class IdealSensor final : public OdorSensorModel {
 public:
  /// Builds it; it draws no random numbers.
  IdealSensor(const IdealSensorParams&, Rng) {}
  bool ideal() const override { return true; }
  void reset(double) override {}
  double read(double c, double) override { return c; }
};

/// A first-order response with a rise and a decay time constant and additive Gaussian noise, as
/// metal-oxide (MOX) gas sensors have (docs/agents.md gives the equations and where the defaults
/// come from).
struct FirstOrderSensorParams {
  /// Time constant while the concentration is above the state (s). why: 2.96 s, GADEN's
  /// Figaro TGS2620 (Monroy et al. 2017, Sensors 17:1479; docs/agents.md, "Sensor models").
  double tau_rise = 2.96;
  /// Time constant while the concentration is below the state (s). why: 15.71 s, GADEN's TGS2620,
  /// as above; MOX sensors recover in tens of seconds (Monroy et al. 2012, Sensors 12:13664).
  double tau_decay = 15.71;
  /// Standard deviation of the additive noise on each reading (concentration units). why: 0: no
  /// published MOX noise level carries over to this plume's concentration units, and GADEN adds
  /// none; set it for a task.
  double noise = 0.0;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("tau_rise", tau_rise, "rise time constant of the response (s)",
      NumberSpec{.min = 0.0, .max = 1e4});
    v("tau_decay", tau_decay, "decay (recovery) time constant of the response (s)",
      NumberSpec{.min = 0.0, .max = 1e4});
    v("noise", noise, "std of the additive noise on each reading (concentration units)",
      kNonNegative);
  }
};

/// The first-order sensor: y += (c - y) (1 - exp(-dt / tau)), tau = tau_rise when c > y else
/// tau_decay (0: no lag), then reading = max(0, y + noise * N(0, 1)).
class FirstOrderSensor final : public OdorSensorModel {
 public:
  /// Builds it with its own random stream.
  FirstOrderSensor(const FirstOrderSensorParams& params, Rng rng) : params_(params), rng_(rng) {}
  void reset(double c) override { state_ = c; }
  double read(double c, double dt) override;
  /// The noiseless state (concentration units).
  double state() const { return state_; }

 private:
  // the weight of the new concentration for a time constant: 1 - exp(-dt / tau), cached per dt
  double gain(double tau, double dt, double& cached_dt, double& cached) const;

  FirstOrderSensorParams params_;
  Rng rng_;
  double state_ = 0.0;
  double rise_dt_ = -1.0, rise_gain_ = 1.0, decay_dt_ = -1.0, decay_gain_ = 1.0;
};

/// The odor sensor models, chosen by odor.model: made from their params and the robot's sensor
/// stream.
using SensorModelRegistry = Registry<OdorSensorModel, Rng>;

/// The registered sensor models (src/agent/sensor_models.cpp: one line each).
SensorModelRegistry& sensor_model_registry();

/// Which sensor model: its place in sensor_model_registry().
enum class SensorModel : int { kIdeal, kFirstOrder };

}  // namespace plumetrace

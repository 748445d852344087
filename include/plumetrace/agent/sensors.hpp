#pragma once

#include <memory>

#include "plumetrace/agent/measurement.hpp"
#include "plumetrace/agent/sensor_models.hpp"
#include "plumetrace/core/config.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/rng.hpp"
#include "plumetrace/env/odor.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {

/// The odor sensor (docs/model.md section 4.7; docs/agents.md, "Sensor models"): a sensor model
/// turns the concentration at the sensor into a reading; the binary odor is the reading's
/// threshold test.
struct OdorSensorParams {
  /// Concentration at or above which odor is perceived.
  double threshold = 100.0;
  /// Height of the sensor above the release centre (m). why: 0.07, the robot model's sensors 7 cm
  /// up with the release centre at the floor (docs/fidelity.md, unknown 8 and "Which reading
  /// won").
  double height = 0.07;
  /// The sensor model. why: "ideal", the paper's binary sensor, which perceives the
  /// concentration at once and without noise.
  SensorModel model = SensorModel::kIdeal;
  /// The params of every registered sensor model.
  FamilyParams<SensorModelRegistry> models;

  /// The params struct P (FirstOrderSensorParams, ...) of its model.
  template <class P>
  P& get() {
    return models.get<P>(sensor_model_registry());
  }
  /// The params struct P of its model.
  template <class P>
  const P& get() const {
    return models.get<P>(sensor_model_registry());
  }

  /// The config keys: threshold, height, model, then the table of every sensor model.
  void fields(FieldVisitor& v);
  /// Reads the config keys without writing.
  void read_fields(FieldReader& v) const;
};

/// Builds the sensor model of a robot's odor sensor with its random stream.
std::unique_ptr<OdorSensorModel> make_sensor_model(const OdorSensorParams& params, Rng rng);

/// Wind-direction sensor (paper eqs. 6-7).
struct WindSensorParams {
  /// Standard deviation of the noise on each wind component (m/s), before sigma_a_scale.
  double sigma_a = 0.1;
  /// Factor on sigma_a: the noise std applied is sigma_a * sigma_a_scale (the unit of the
  /// printed value).
  double sigma_a_scale = 1.0;
  /// Independent noisy samples averaged into one measurement (noise std / sqrt(samples)).
  int samples = 1;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("sigma_a", sigma_a, "noise std on each wind component (m/s)", kNonNegative);
    v("sigma_a_scale", sigma_a_scale, "factor on sigma_a: the noise std is sigma_a * sigma_a_scale",
      NumberSpec{.min = 0.0, .max = 100.0});
    v("samples", samples, "noisy samples averaged into one wind measurement", IntegerSpec{1, 1000});
  }
};

/// Where the odor sensor of a robot at `pose` samples the plume.
inline Vec3 odor_sensor_point(const OdorSensorParams& params, const Pose& pose) {
  return {pose.x, pose.y, params.height};
}

/// Concentration at the odor sensor of a robot at `pose` (a point sample, no noise).
double sense_concentration(const OdorSensorParams& params, const OdorField& odor, const Pose& pose);

/// Binary odor at the sensor of a robot at `pose`: the concentration reaches the threshold.
inline bool sense_odor(const OdorSensorParams& params, const OdorField& odor, const Pose& pose) {
  return odor.reaches(odor_sensor_point(params, pose), params.threshold);
}

/// Binary odor: the concentration reaches the threshold.
inline bool perceives_odor(const OdorSensorParams& params, double concentration) {
  return concentration >= params.threshold;
}

/// A noisy wind measurement at `pose` in the wind as it is now (the mean of params.samples
/// samples), rotated into the robot frame (3-D, m/s).
Vec3 sense_wind_body(const WindSensorParams& params, const WindField& wind, const Pose& pose,
                     double height, Rng& rng);

/// The wind sensor bound to the true world, as a controller sees it; records its samples.
class WindSensor final : public WindProbe {
 public:
  /// Binds the sensor to the wind field (the environment's own, which the plume moves in), the
  /// robot pose it reads, and its random stream.
  WindSensor(const WindSensorParams& params, const WindField& wind, const Pose& pose, double height,
             Rng& rng)
      : params_(params), wind_(wind), pose_(pose), height_(height), rng_(rng) {}

  Vec2 measure_wind_body() override;
  /// Samples taken since the last clear (for traces).
  int samples() const { return samples_; }
  /// Last sample in the robot frame (m/s).
  const Vec3& last_sample() const { return last_; }
  /// Resets the per-step sample count.
  void clear() { samples_ = 0; }
  /// Total samples taken.
  long total() const { return total_; }

 private:
  const WindSensorParams& params_;
  const WindField& wind_;
  const Pose& pose_;
  double height_;
  Rng& rng_;
  int samples_ = 0;
  long total_ = 0;
  Vec3 last_;
};

}  // namespace plumetrace

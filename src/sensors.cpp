#include "plumetrace/sensors.hpp"

namespace plumetrace {

double sense_concentration(const OdorSensorParams& params, const Plume& plume, const Pose& pose) {
  return plume.concentration(odor_sensor_point(params, pose));
}

Vec3 sense_wind_body(const WindSensorParams& params, const WindField& wind, const Pose& pose,
                     double height, double t, Rng& rng) {
  // true wind plus independent noise on each component, then into the robot frame (eqs. 6-7)
  const Vec3 a = wind.velocity({pose.x, pose.y, height}, t);
  const double nx = rng.normal(), ny = rng.normal(), nz = rng.normal();
  const Vec2 world{a.x + params.sigma_a * nx, a.y + params.sigma_a * ny};
  const Vec2 body = rotate(world, -pose.heading);
  return {body.x, body.y, a.z + params.sigma_a * nz};
}

Vec2 WindSensor::measure_wind_body() {
  last_ = sense_wind_body(params_, wind_, pose_, height_, time_, rng_);
  ++samples_;
  ++total_;
  return {last_.x, last_.y};
}

}  // namespace plumetrace

#include "plumetrace/agent/sensors.hpp"

namespace plumetrace {

double sense_concentration(const OdorSensorParams& params, const OdorField& odor,
                           const Pose& pose) {
  return odor.concentration(odor_sensor_point(params, pose));
}

Vec3 sense_wind_body(const WindSensorParams& params, const WindField& wind, const Pose& pose,
                     double height, Rng& rng) {
  // true wind plus independent noise on each component, then into the robot frame (eqs. 6-7)
  const Vec3 a = wind.velocity({pose.x, pose.y, height});
  const double sigma = params.sigma_a * params.sigma_a_scale;
  // the mean of n samples of the same wind: the mean of n noise draws, x, y, z per sample
  // why: with n = 1 the means are the draws themselves, so the stream and values are as before
  double nx = rng.normal(), ny = rng.normal(), nz = rng.normal();
  for (int i = 1; i < params.samples; ++i) {
    nx += rng.normal();
    ny += rng.normal();
    nz += rng.normal();
  }
  const double n = static_cast<double>(params.samples);
  nx /= n;
  ny /= n;
  nz /= n;
  const Vec2 world{a.x + sigma * nx, a.y + sigma * ny};
  const Vec2 body = rotate(world, -pose.heading);
  return {body.x, body.y, a.z + sigma * nz};
}

Vec2 WindSensor::measure_wind_body() {
  last_ = sense_wind_body(params_, wind_, pose_, height_, rng_);
  ++samples_;
  ++total_;
  return {last_.x, last_.y};
}

}  // namespace plumetrace

#include "plumetrace/agent/sensors.hpp"

#include <string>

#include "plumetrace/core/errors.hpp"

namespace plumetrace {

namespace {

constexpr const char* kModelHelp = "odor sensor model: ideal (the paper's) or first-order (MOX-like)";

}  // namespace

void OdorSensorParams::fields(FieldVisitor& v) {
  const SensorModelRegistry& registry = sensor_model_registry();
  v("threshold", threshold, "concentration at which odor is perceived", kPositive);
  v("height", height, "odor and wind sensor height (m)", kAnyNumber);
  v("model", model, kModelHelp, registry.names());
  models.fields(registry, v);
}

void OdorSensorParams::read_fields(FieldReader& v) const {
  // why: a FieldReader never writes through the references it is handed
  auto& self = const_cast<OdorSensorParams&>(*this);
  FieldVisitor& w = v;
  const SensorModelRegistry& registry = sensor_model_registry();
  w("threshold", self.threshold, "concentration at which odor is perceived", kPositive);
  w("height", self.height, "odor and wind sensor height (m)", kAnyNumber);
  w("model", self.model, kModelHelp, registry.names());
  models.read_fields(registry, v);
}

std::unique_ptr<OdorSensorModel> make_sensor_model(const OdorSensorParams& params, Rng rng) {
  const SensorModelRegistry& registry = sensor_model_registry();
  const auto i = static_cast<std::size_t>(params.model);
  if (i >= registry.size()) {
    throw ConfigError("odor.model: unknown sensor model (index " + std::to_string(i) + ")");
  }
  return registry[i].make(params.models.at(registry, i), rng);
}

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

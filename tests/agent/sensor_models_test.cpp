// Tests of agent/sensor_models.hpp: the ideal and first-order odor sensors (docs/agents.md).
#include "plumetrace/agent/sensor_models.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "plumetrace/agent/sensors.hpp"
#include "plumetrace/core/rng.hpp"

namespace plumetrace {
namespace {

TEST(SensorModels, TheIdealSensorReadsTheConcentration) {
  IdealSensor s(IdealSensorParams{}, Rng(1));
  EXPECT_TRUE(s.ideal());
  EXPECT_EQ(s.read(123.5, 0.032), 123.5);
  EXPECT_EQ(s.read(0.0, 0.032), 0.0);
}

TEST(SensorModels, TheFirstOrderSensorFollowsItsExponentialResponse) {
  FirstOrderSensorParams p;  // GADEN's TGS2620: 2.96 s up, 15.71 s down
  FirstOrderSensor s(p, Rng(1));
  EXPECT_FALSE(s.ideal());
  s.reset(0.0);
  const double dt = 0.032, c = 400.0;
  double y = 0.0;
  for (int k = 1; k <= 200; ++k) y = s.read(c, dt);
  // a step up: c (1 - exp(-t / tau_rise)) at t = 6.4 s
  EXPECT_NEAR(y, c * (1.0 - std::exp(-200 * dt / p.tau_rise)), 1e-9 * c);
  // then a step down to 0: y0 exp(-t / tau_decay)
  const double y0 = y;
  for (int k = 1; k <= 300; ++k) y = s.read(0.0, dt);
  EXPECT_NEAR(y, y0 * std::exp(-300 * dt / p.tau_decay), 1e-9 * c);
  // recovery is slower than rise: after equal times the fall is the smaller fraction
  EXPECT_GT(y / y0, std::exp(-300 * dt / p.tau_rise));
}

TEST(SensorModels, ATimeConstantOfZeroHasNoLag) {
  FirstOrderSensorParams p;
  p.tau_rise = 0.0;
  p.tau_decay = 0.0;
  FirstOrderSensor s(p, Rng(1));
  s.reset(5.0);
  EXPECT_EQ(s.read(300.0, 0.032), 300.0);
  EXPECT_EQ(s.read(2.0, 0.032), 2.0);
}

TEST(SensorModels, NoiseIsAdditiveGaussianWithItsStandardDeviation) {
  FirstOrderSensorParams p;
  p.noise = 10.0;
  FirstOrderSensor s(p, Rng(7));
  s.reset(1000.0);
  const int n = 20000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double e = s.read(1000.0, 0.032) - 1000.0;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4.0 * p.noise / std::sqrt(n));
  // the sample std of n normal draws has a standard error of about sigma / sqrt(2 n)
  EXPECT_NEAR(sd, p.noise, 4.0 * p.noise / std::sqrt(2.0 * n));
  // a reading is never negative
  s.reset(0.0);
  for (int k = 0; k < 1000; ++k) EXPECT_GE(s.read(0.0, 0.032), 0.0);
}

TEST(SensorModels, TheRegistryBuildsTheChosenModel) {
  OdorSensorParams params;
  EXPECT_TRUE(make_sensor_model(params, Rng(1))->ideal());
  params.model = SensorModel::kFirstOrder;
  params.get<FirstOrderSensorParams>().tau_rise = 0.0;
  auto m = make_sensor_model(params, Rng(1));
  EXPECT_FALSE(m->ideal());
  m->reset(0.0);
  EXPECT_EQ(m->read(50.0, 0.1), 50.0);  // the params written reached the model
}

}  // namespace
}  // namespace plumetrace

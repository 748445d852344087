#include "plumetrace/agent/sensors.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "plumetrace/agent/measurement.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/rng.hpp"
#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {
namespace {

constexpr double kDt = 0.032;

// Running first and second moments of one component.
struct Moments {
  double s1 = 0.0, s2 = 0.0;
  void add(double v) {
    s1 += v;
    s2 += v * v;
  }
};

// Checks sample mean and standard deviation against a normal(mean, stddev), 4 sigma.
void expect_normal(const Moments& m, double n, double mean, double stddev) {
  const double sample_mean = m.s1 / n;
  const double sample_var = m.s2 / n - sample_mean * sample_mean;
  const double var = stddev * stddev;
  EXPECT_NEAR(sample_mean, mean, 4.0 * stddev / std::sqrt(n));
  EXPECT_NEAR(sample_var, var, 4.0 * std::sqrt(2.0 / n) * var);
}

TEST(WindSensor, NoiseHasTrueMeanAndSigmaPerComponent) {
  const WindSensorParams params;
  ASSERT_EQ(params.sigma_a, 0.1);
  const ConstantWind wind({1.0, 0.0, 0.0});
  const Pose pose{4.0, 0.3, 0.7};
  Rng rng(12345);
  const int n = 200000;
  Moments mx, my, mz;
  double sxy = 0.0, sxz = 0.0, syz = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec3 body = sense_wind_body(params, wind, pose, 0.0, rng);
    // back into the world frame
    const Vec2 world = rotate({body.x, body.y}, pose.heading);
    mx.add(world.x);
    my.add(world.y);
    mz.add(body.z);
    sxy += (world.x - 1.0) * world.y;
    sxz += (world.x - 1.0) * body.z;
    syz += world.y * body.z;
  }
  expect_normal(mx, n, 1.0, 0.1);
  expect_normal(my, n, 0.0, 0.1);
  expect_normal(mz, n, 0.0, 0.1);
  // independent components: each covariance has standard error sigma^2 / sqrt(n)
  const double cov_bound = 4.0 * 0.01 / std::sqrt(static_cast<double>(n));
  EXPECT_NEAR(sxy / n, 0.0, cov_bound);
  EXPECT_NEAR(sxz / n, 0.0, cov_bound);
  EXPECT_NEAR(syz / n, 0.0, cov_bound);
}

// World-frame moments of many measurements at a fixed pose under the given parameters.
struct WorldMoments {
  Moments x, y, z;
  double n = 0.0;
};

WorldMoments measure_many(const WindSensorParams& params, int n, std::uint64_t seed) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  const Pose pose{4.0, 0.3, 0.7};
  Rng rng(seed);
  WorldMoments m;
  m.n = n;
  for (int i = 0; i < n; ++i) {
    const Vec3 body = sense_wind_body(params, wind, pose, 0.0, rng);
    const Vec2 world = rotate({body.x, body.y}, pose.heading);
    m.x.add(world.x);
    m.y.add(world.y);
    m.z.add(body.z);
  }
  return m;
}

TEST(WindSensor, MeanOfNSamplesHasSigmaOverSqrtN) {
  for (int samples : {4, 9}) {
    WindSensorParams params;
    params.samples = samples;
    const WorldMoments m = measure_many(params, 100000, 777);
    const double stddev = 0.1 / std::sqrt(static_cast<double>(samples));
    expect_normal(m.x, m.n, 1.0, stddev);
    expect_normal(m.y, m.n, 0.0, stddev);
    expect_normal(m.z, m.n, 0.0, stddev);
  }
}

TEST(WindSensor, OneSampleDrawsExactlyAsTheSingleSampleSensor) {
  // the single-sample sensor: wind plus sigma_a times one normal draw per component
  const WindSensorParams params;
  ASSERT_EQ(params.samples, 1);
  const ConstantWind wind({1.0, 0.0, 0.0});
  Rng rng(99), reference(99);
  for (int i = 0; i < 1000; ++i) {
    const Pose pose{4.0, 0.3, 0.01 * i};
    const Vec3 body = sense_wind_body(params, wind, pose, 0.0, rng);
    const double nx = reference.normal(), ny = reference.normal(), nz = reference.normal();
    const Vec2 expected = rotate({1.0 + 0.1 * nx, 0.0 + 0.1 * ny}, -pose.heading);
    ASSERT_EQ(body.x, expected.x) << i;
    ASSERT_EQ(body.y, expected.y) << i;
    ASSERT_EQ(body.z, 0.0 + 0.1 * nz) << i;
  }
  EXPECT_EQ(rng.next_u64(), reference.next_u64());
}

TEST(WindSensor, NSamplesTakeThreeNormalDrawsEach) {
  WindSensorParams params;
  params.samples = 5;
  const ConstantWind wind({1.0, 0.0, 0.0});
  Rng rng(5), reference(5);
  sense_wind_body(params, wind, {4.0, 0.0, 0.0}, 0.0, rng);
  for (int i = 0; i < 15; ++i) reference.normal();
  EXPECT_EQ(rng.next_u64(), reference.next_u64());
}

TEST(WindSensor, SigmaScaleMultipliesSigmaA) {
  // sigma_a 0.1 read in units twice as large is the same sensor as sigma_a 0.2
  WindSensorParams scaled, plain;
  scaled.sigma_a = 0.1;
  scaled.sigma_a_scale = 2.0;
  plain.sigma_a = 0.2;
  const ConstantWind wind({1.0, 0.0, 0.0});
  Rng a(31), b(31);
  for (int i = 0; i < 1000; ++i) {
    const Pose pose{4.0, 0.3, 0.01 * i};
    const Vec3 u = sense_wind_body(scaled, wind, pose, 0.0, a);
    const Vec3 v = sense_wind_body(plain, wind, pose, 0.0, b);
    ASSERT_EQ(u.x, v.x) << i;
    ASSERT_EQ(u.y, v.y) << i;
    ASSERT_EQ(u.z, v.z) << i;
  }
  // and the noise std is sigma_a * sigma_a_scale, also with several samples
  WindSensorParams params;
  params.sigma_a_scale = 3.0;
  params.samples = 4;
  const WorldMoments m = measure_many(params, 100000, 4242);
  expect_normal(m.x, m.n, 1.0, 0.3 / 2.0);
  expect_normal(m.y, m.n, 0.0, 0.3 / 2.0);
  expect_normal(m.z, m.n, 0.0, 0.3 / 2.0);
}

TEST(WindSensor, BodyFrameIsWorldWindRotatedByMinusHeading) {
  WindSensorParams params;
  params.sigma_a = 0.0;
  const ConstantWind wind({1.0, 0.0, 0.0});
  Rng rng(1);
  const auto body = [&](double heading) {
    return sense_wind_body(params, wind, {5.0, 0.0, heading}, 0.0, rng);
  };
  // facing downwind the wind comes from behind
  EXPECT_NEAR(body(0.0).x, 1.0, 1e-15);
  EXPECT_NEAR(body(0.0).y, 0.0, 1e-15);
  // facing upwind (the start pose) the wind blows straight at the robot
  EXPECT_NEAR(body(kPi).x, -1.0, 1e-15);
  EXPECT_NEAR(body(kPi).y, 0.0, 1e-15);
  // facing +y the wind blows from the left to the right (-y in the body frame)
  EXPECT_NEAR(body(kPi / 2).x, 0.0, 1e-15);
  EXPECT_NEAR(body(kPi / 2).y, -1.0, 1e-15);
  EXPECT_NEAR(body(-kPi / 2).x, 0.0, 1e-15);
  EXPECT_NEAR(body(-kPi / 2).y, 1.0, 1e-15);
  for (int k = -12; k <= 12; ++k) {
    const double h = k * kPi / 12.0 + 0.01;
    const Vec3 b = body(h);
    EXPECT_NEAR(b.x, std::cos(-h), 1e-15);
    EXPECT_NEAR(b.y, std::sin(-h), 1e-15);
    EXPECT_EQ(b.z, 0.0);
  }
}

TEST(WindSensor, VerticalComponentIsNotRotated) {
  WindSensorParams params;
  params.sigma_a = 0.0;
  const ConstantWind wind({0.6, 0.8, -0.25});
  Rng rng(1);
  const Vec3 b = sense_wind_body(params, wind, {5.0, 0.0, 2.0}, 0.0, rng);
  EXPECT_EQ(b.z, -0.25);
  const Vec2 expected = rotate({0.6, 0.8}, -2.0);
  EXPECT_NEAR(b.x, expected.x, 1e-15);
  EXPECT_NEAR(b.y, expected.y, 1e-15);
  // rotation keeps the horizontal speed
  EXPECT_NEAR(std::hypot(b.x, b.y), 1.0, 1e-15);
}

TEST(WindSensor, UpwindHeadingIsPiForAnyRobotHeading) {
  WindSensorParams params;
  params.sigma_a = 0.0;
  const ConstantWind wind({1.0, 0.0, 0.0});
  Rng rng(1);
  for (int k = -36; k < 36; ++k) {
    const double h = k * kPi / 36.0 + 0.003;
    const Vec3 b = sense_wind_body(params, wind, {5.0, 1.0, h}, 0.0, rng);
    const double upwind = upwind_heading({b.x, b.y}, h);
    EXPECT_NEAR(wrap_angle(upwind - kPi), 0.0, 1e-12) << "heading " << h;
  }
}

TEST(WindSensor, UpwindHeadingOfOtherWindDirections) {
  WindSensorParams params;
  params.sigma_a = 0.0;
  Rng rng(1);
  for (int j = 0; j < 8; ++j) {
    const double from = j * kPi / 4.0;  // the direction the wind comes from
    const ConstantWind wind({-std::cos(from), -std::sin(from), 0.0});
    for (int k = 0; k < 8; ++k) {
      const double h = k * kPi / 4.0 - 0.2;
      const Vec3 b = sense_wind_body(params, wind, {5.0, 1.0, h}, 0.0, rng);
      EXPECT_NEAR(wrap_angle(upwind_heading({b.x, b.y}, h) - from), 0.0, 1e-12);
    }
  }
}

TEST(WindSensor, CountsSamplesAndReadsTheBoundPose) {
  WindSensorParams params;
  params.sigma_a = 0.0;
  const ConstantWind wind({1.0, 0.0, 0.0});
  Pose pose{3.0, 0.0, kPi};
  Rng rng(9);
  WindSensor sensor(params, wind, pose, 0.0, rng);
  EXPECT_EQ(sensor.samples(), 0);
  EXPECT_EQ(sensor.total(), 0);
  Vec2 v = sensor.measure_wind_body();
  EXPECT_NEAR(v.x, -1.0, 1e-15);
  EXPECT_NEAR(v.y, 0.0, 1e-15);
  // the sensor follows the pose it is bound to
  pose.heading = kPi / 2;
  v = sensor.measure_wind_body();
  EXPECT_NEAR(v.x, 0.0, 1e-15);
  EXPECT_NEAR(v.y, -1.0, 1e-15);
  EXPECT_EQ(sensor.last_sample().x, v.x);
  EXPECT_EQ(sensor.last_sample().y, v.y);
  sensor.measure_wind_body();
  EXPECT_EQ(sensor.samples(), 3);
  EXPECT_EQ(sensor.total(), 3);
  sensor.clear();
  EXPECT_EQ(sensor.samples(), 0);
  EXPECT_EQ(sensor.total(), 3);
  sensor.measure_wind_body();
  EXPECT_EQ(sensor.samples(), 1);
  EXPECT_EQ(sensor.total(), 4);
}

TEST(WindSensor, ClassDrawsTheSameNoiseAsTheFunction) {
  const WindSensorParams params;
  const ConstantWind wind({1.0, 0.0, 0.0});
  const Pose pose{7.0, -0.2, 2.5};
  Rng a(31), b(31);
  WindSensor sensor(params, wind, pose, 0.0, a);
  for (int i = 0; i < 100; ++i) {
    const Vec2 got = sensor.measure_wind_body();
    const Vec3 want = sense_wind_body(params, wind, pose, 0.0, b);
    EXPECT_EQ(got.x, want.x);
    EXPECT_EQ(got.y, want.y);
  }
}

// A default plume after some seconds, so that concentrations vary over the probed points.
FilamentPlume warm_plume() {
  const ConstantWind wind({1.0, 0.0, 0.0});
  PlumeParams params;
  params.amount = 8.3e9;  // the printed amount: a dense plume far above threshold near its axis
  FilamentPlume plume(params, SourceParams{}, 16.0, 21);
  for (int k = 0; k < 300; ++k) plume.step(wind, kDt);
  return plume;
}

TEST(OdorSensor, SamplesPlumeConcentrationAtRobotAndSensorHeight) {
  const FilamentPlume plume = warm_plume();
  OdorSensorParams params;
  EXPECT_EQ(params.threshold, 100.0);
  EXPECT_EQ(params.height, 0.07);
  for (const double height : {0.0, 0.05, -0.1}) {
    params.height = height;
    for (const Pose& pose :
         {Pose{1.0, 0.0, 0.0}, Pose{3.0, 0.1, 1.0}, Pose{5.0, -0.4, kPi}, Pose{8.0, 0.9, -2.0}}) {
      EXPECT_EQ(sense_concentration(params, plume, pose),
                plume.concentration({pose.x, pose.y, height}));
    }
  }
  // the heading plays no part in a point sample
  params.height = 0.0;
  EXPECT_EQ(sense_concentration(params, plume, {3.0, 0.1, 0.0}),
            sense_concentration(params, plume, {3.0, 0.1, 2.0}));
  // inside the young plume the sample is far above threshold, 3 m to the side it is zero
  EXPECT_GT(sense_concentration(params, plume, {2.0, 0.0, 0.0}), 1e6);
  EXPECT_EQ(sense_concentration(params, plume, {2.0, 3.0, 0.0}), 0.0);
}

TEST(OdorSensor, PerceivesOdorAtOrAboveThreshold) {
  OdorSensorParams params;
  EXPECT_FALSE(perceives_odor(params, 0.0));
  EXPECT_FALSE(perceives_odor(params, 99.999));
  EXPECT_FALSE(perceives_odor(params, std::nextafter(100.0, 0.0)));
  EXPECT_TRUE(perceives_odor(params, 100.0));
  EXPECT_TRUE(perceives_odor(params, 100.001));
  EXPECT_TRUE(perceives_odor(params, 1e12));
  params.threshold = 5.0;
  EXPECT_FALSE(perceives_odor(params, 4.999));
  EXPECT_TRUE(perceives_odor(params, 5.0));
}

}  // namespace
}  // namespace plumetrace

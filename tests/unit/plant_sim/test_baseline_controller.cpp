// The baseline controller on its own (measured samples in, references out), and the wind field's LIDAR and
// frozen-turbulence transport, without the rest of the plant.
#include <gtest/gtest.h>

#include <cmath>

#include "baseline_controller.hpp"
#include "lidar_shear.hpp"
#include "wind_field.hpp"

using namespace windfdi;
using namespace windfdi::plant;

namespace {

constexpr double kDt = 0.01;

FrameSample sample_at(double generator_speed, double azimuth = 0.0) {
  FrameSample s;
  s.generator_speed = generator_speed;
  s.rotor_speed = generator_speed / TurbineParams{}.gear_ratio;
  s.azimuth = azimuth;
  s.blade_moment = {3e6, 3e6, 3e6};
  return s;
}

BaselineController controller_at(double pitch, double generator_speed) {
  BaselineController c(TurbineParams{}, ControllerParams{}, 100.0, 12.0, kDt);
  c.start_at(pitch, generator_speed);
  return c;
}

}  // namespace

TEST(BaselineController, BelowRatedTorqueIsKOmegaSquaredAndPitchStaysFine) {
  // GIVEN a settled controller at a generator speed well below rated (region 2)
  const TurbineParams p;
  BaselineController c = controller_at(0.0, 100.0);
  ControllerOutput out;
  for (int k = 0; k < 100; ++k) out = c.step(k * kDt, ControlInput{}, sample_at(100.0), false, 0.0);
  // THEN the torque is K omega^2 with K from Cp's maximum, and the pitch stays at fine pitch
  const double lambda = AeroModel::optimal_tip_speed_ratio();
  const double k_opt = 0.5 * p.air_density * p.rotor_area() * std::pow(p.rotor_radius, 3) *
                       AeroModel::power_coefficient(lambda, 0.0) / std::pow(lambda, 3) /
                       std::pow(p.gear_ratio, 3);
  EXPECT_NEAR(out.torque_ref, k_opt * 100.0 * 100.0, 1e-6 * k_opt * 1e4);
  for (double b : out.pitch_ref) EXPECT_DOUBLE_EQ(b, 0.0);
}

TEST(BaselineController, AboveRatedSpeedPitchesOutAndDegradedModePitchesFurther) {
  // GIVEN the measured speed 3 % above rated for 5 s, in normal and in degraded mode
  const TurbineParams p;
  const double speed = 1.03 * p.rated_generator_speed;
  BaselineController normal = controller_at(10.0, speed), degraded = controller_at(10.0, speed);
  ControlInput degraded_input;
  degraded_input.mode = OperatingMode::kDegraded;
  ControllerOutput n, d;
  for (int k = 0; k < 500; ++k) {
    n = normal.step(k * kDt, ControlInput{}, sample_at(speed), false, 0.0);
    d = degraded.step(k * kDt, degraded_input, sample_at(speed), false, 0.0);
  }
  // THEN the PI pitches out, further when the speed reference is the degraded one, and the torque is capped
  // at the (degraded) rated power
  EXPECT_GT(n.pitch_ref[0], 10.0);
  EXPECT_GT(d.pitch_ref[0], n.pitch_ref[0] + 1.0);
  EXPECT_NEAR(n.torque_ref, p.rated_power / (p.generator_efficiency * p.rated_generator_speed), 1.0);
  const ControllerParams ctl;
  EXPECT_NEAR(d.torque_ref,
              p.rated_power * ctl.degraded_power /
                  (p.generator_efficiency * ctl.degraded_speed * p.rated_generator_speed),
              1.0);
}

TEST(BaselineController, SafeStopFeathersAndRampsTheTorqueToZero) {
  const TurbineParams p;
  BaselineController c = controller_at(10.0, p.rated_generator_speed);
  ControlInput stop;
  stop.mode = OperatingMode::kSafeStop;
  // GIVEN a converter at 30 kN m that follows the torque reference
  double torque = 3e4;
  ControllerOutput out = c.step(0.0, stop, sample_at(p.rated_generator_speed), false, torque);
  // THEN every blade is sent to feather at once and the torque decays without a step: by 1/e of the way
  // (plus the 1 N m per sample) in one time constant, and to zero after tau ln((T0 + 1000) / 1000) = 34 s
  for (double b : out.pitch_ref) EXPECT_DOUBLE_EQ(b, p.pitch_max);
  EXPECT_LT(out.torque_ref, torque);
  EXPECT_GT(out.torque_ref, 0.99 * torque);
  const double tau = ControllerParams{}.stop_torque_time;
  int k = 1;
  for (; k < 6000 && out.torque_ref > 0.0; ++k) {
    EXPECT_LE(out.torque_ref, torque);
    torque = out.torque_ref;
    if (k == static_cast<int>(tau / kDt)) {
      EXPECT_NEAR(torque, 31e3 / M_E - 1e3, 300.0);
    }
    out = c.step(k * kDt, stop, sample_at(p.rated_generator_speed), false, torque);
  }
  EXPECT_DOUBLE_EQ(out.torque_ref, 0.0);
  EXPECT_NEAR(k * kDt, tau * std::log(31.0), 0.5);
}

TEST(BaselineController, CorrectedSpeedReplacesTheMeasuredOneOnlyWhenKnown) {
  const TurbineParams p;
  // GIVEN a generator-speed sensor that reads 10 % high at rated speed
  const double truth = p.rated_generator_speed, biased = 1.1 * truth;
  ControlInput corrected;
  corrected.use_corrected_generator_speed = true;
  corrected.corrected_generator_speed = truth;
  ControlInput unknown = corrected;
  unknown.corrected_generator_speed = kNaN;
  BaselineController a = controller_at(10.0, truth), b = controller_at(10.0, truth);
  ControllerOutput with, without;
  for (int k = 0; k < 300; ++k) {
    with = a.step(k * kDt, corrected, sample_at(biased), false, 0.0);
    without = b.step(k * kDt, unknown, sample_at(biased), false, 0.0);
  }
  // THEN with the corrected speed the pitch holds (no speed error); without a corrected value it pitches out
  EXPECT_NEAR(with.pitch_ref[0], 10.0, 0.05);
  EXPECT_GT(without.pitch_ref[0], 12.0);
}

TEST(BaselineController, IpcActsOnA1pLoadFromTheGaugesOrTheLidarModelAndNotWithoutAKnownLoad) {
  const TurbineParams p;
  // GIVEN above-rated operation with a 1P load: blade moment M0 + M1 cos(psi_i)
  auto loaded = [&](double t) {
    const double azimuth = std::fmod(1.2 * t, 2.0 * M_PI);
    FrameSample s = sample_at(p.rated_generator_speed, azimuth);
    for (int i = 0; i < 3; ++i) s.blade_moment[i] = 3e6 + 1e6 * std::cos(azimuth + i * 2.0 * M_PI / 3.0);
    return s;
  };
  ControlInput gauges, lidar_model;
  lidar_model.ipc_source = IpcSource::kLidarModel;
  BaselineController g = controller_at(10.0, p.rated_generator_speed),
                     blind = controller_at(10.0, p.rated_generator_speed),
                     sheared = controller_at(10.0, p.rated_generator_speed);
  double spread_gauges = 0.0, spread_blind = 0.0, spread_sheared = 0.0;
  for (int k = 0; k < 3000; ++k) {
    const double t = k * kDt;
    const ControllerOutput a = g.step(t, gauges, loaded(t), false, 0.0);
    // No LIDAR measurement ever arrives: the LIDAR model knows no load.
    const ControllerOutput b = blind.step(t, lidar_model, loaded(t), false, 0.0);
    // A sheared wind (14 m/s on the upper beam, 12 on the lower) measured at 10 Hz: a 1P load the model
    // computes once the first measurement has reached the rotor (D / V = 100 m / 13 m/s).
    FrameSample s = loaded(t);
    s.lidar_v_upper = 14.0;
    s.lidar_v_lower = 12.0;
    const ControllerOutput c = sheared.step(t, lidar_model, s, k % 10 == 0, 0.0);
    if (k > 2500) {
      spread_gauges = std::max(spread_gauges, std::fabs(a.pitch_ref[0] - a.pitch_ref[1]));
      spread_blind = std::max(spread_blind, std::fabs(b.pitch_ref[0] - b.pitch_ref[1]));
      spread_sheared = std::max(spread_sheared, std::fabs(c.pitch_ref[0] - c.pitch_ref[1]));
    }
  }
  // THEN IPC moves the blades apart on the gauges' 1P load and on the LIDAR model's sheared wind, and not at
  // all on an unknown LIDAR-model load
  EXPECT_GT(spread_gauges, 0.5);
  EXPECT_GT(spread_sheared, 0.1);
  EXPECT_DOUBLE_EQ(spread_blind, 0.0);
}

TEST(WindField, LidarBeamsGiveTheShearAndTheRotorSeesTheUpstreamWindDOverVLater) {
  // GIVEN steady 10 m/s with shear 0.2, LIDAR 100 m upstream, no turbulence or LIDAR noise
  WindConfig w;
  w.mean = 10.0;
  w.turbulence_intensity = 0.0;
  w.lidar_noise = 0.0;
  const TurbineParams p;
  WindField field(w, p, kDt);
  RandomSource random(1);
  for (int k = 0; k < 20; ++k) field.step(random);
  // THEN the two beams give back the profile's exponent and hub speed
  const ShearProfile seen =
      shear_from_beams(field.lidar_upper(), field.lidar_lower(), p.hub_height, 0.5 * p.rotor_radius);
  EXPECT_NEAR(seen.exponent, 0.2, 1e-12);
  EXPECT_NEAR(seen.hub_speed, 10.0, 1e-12);
  EXPECT_NEAR(field.at_rotor().hub_speed, 10.0, 1e-12);

  // AND with turbulence, the rotor wind is the upstream wind of D / V = 10 s earlier
  w.turbulence_intensity = 0.1;
  WindField turbulent(w, p, kDt);
  std::vector<double> upstream;
  for (int k = 0; k < 3000; ++k) {
    turbulent.step(random);
    upstream.push_back(turbulent.upstream());
    if (k >= 1000) {
      ASSERT_DOUBLE_EQ(turbulent.at_rotor().hub_speed, upstream[static_cast<std::size_t>(k - 1000)]) << k;
    }
  }
}

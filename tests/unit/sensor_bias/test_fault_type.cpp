// Unit tests of the gain-or-offset test against known values.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fault_type.hpp"

using windfdi::sensor_bias::GainOrOffsetTest;
using Verdict = GainOrOffsetTest::Verdict;

namespace {

// A quantity swinging around `mean` by `swing` (a slow sine, period 20 s at 100 Hz) read with white noise.
struct Quantity {
  double mean, swing, noise;
  std::mt19937_64 rng{7};
  double at(int i) const { return mean + swing * std::sin(2.0 * M_PI * i / 2000.0); }
  double noisy() { return std::normal_distribution<double>(0.0, noise)(rng); }
};

// A generator speed of 160 +- 3 rad/s read as gain x speed + offset with 0.05 rad/s noise, against a witness
// with 0.5 rad/s noise, regressed on the reading (as sensor_bias does), over `samples` at 100 Hz.
GainOrOffsetTest generator_speed_test(double gain, double offset, int samples) {
  Quantity q{160.0, 3.0, 0.5};
  GainOrOffsetTest test(1, true);
  for (int i = 0; i < samples; ++i) {
    const double y = gain * q.at(i) + offset + 0.1 * q.noisy(), w = q.at(i) + q.noisy();
    test.add(y - w, y);
  }
  return test;
}

}  // namespace

TEST(GainOrOffset, AGainOnAMovingQuantityIsAGainWithItsSize) {
  // GIVEN a generator speed of 160 +- 3 rad/s, read with a gain of 0.93 and 0.05 rad/s noise, its witness
  // carrying 0.5 rad/s noise, tested against the reading itself (as sensor_bias does)
  const GainOrOffsetTest test = generator_speed_test(0.93, 0.0, 1000);
  // THEN it is a gain, decided, of 0.93 within 0.005
  EXPECT_EQ(test.verdict(16.0), Verdict::kGain) << test.evidence();
  EXPECT_NEAR(test.gain(), 0.93, 0.005);
}

TEST(GainOrOffset, AnOffsetOnAMovingQuantityIsAnOffsetWithItsSize) {
  // GIVEN the same quantity over a whole swing (20 s), read with a +5 rad/s offset
  const GainOrOffsetTest test = generator_speed_test(1.0, 5.0, 2000);
  // THEN it is an offset of 5 within 0.1
  EXPECT_EQ(test.verdict(16.0), Verdict::kOffset) << test.evidence();
  EXPECT_NEAR(test.offset(), 5.0, 0.1);
}

TEST(GainOrOffset, AtASteadyQuantityNothingIsDecidedAndATieIsTheOffset) {
  // GIVEN a quantity that does not move, read with a gain of 1.07 (the same error as an offset of 0.07 x)
  Quantity q{1.7, 0.0, 0.025};
  GainOrOffsetTest test(50, false);
  for (int i = 0; i < 2000; ++i) {
    const double y = 1.07 * q.at(i) + q.noisy(), w = q.at(i);
    test.add(y - w, w);
  }
  // THEN neither is decided, and with no time left the simpler model, the offset, stands
  EXPECT_EQ(test.verdict(16.0), Verdict::kUndecided) << test.evidence();
  EXPECT_LT(std::fabs(test.evidence()), 2.0);
  EXPECT_EQ(test.verdict_now(2.0), Verdict::kOffset);
}

TEST(GainOrOffset, TheWitnessNoiseSharedByErrorAndRegressorWouldFakeAGain) {
  // GIVEN an offset of -5 rad/s on a quantity with a small swing (0.5 rad/s), the regressor being the noisy
  // witness itself (0.5 rad/s noise, which the error also carries with the opposite sign)
  Quantity q{160.0, 0.5, 0.5};
  GainOrOffsetTest on_witness(1, false), on_reading(1, true);
  for (int i = 0; i < 1000; ++i) {
    const double y = q.at(i) - 5.0, w = q.at(i) + q.noisy();
    on_witness.add(y - w, w);
    on_reading.add(y - w, y);
  }
  // THEN on the witness the shared noise alone fits a negative "gain", decided (why sensor_bias regresses the
  // generator speed on its reading); on the reading nothing is decided, and with no time left it is the
  // offset
  EXPECT_EQ(on_witness.verdict(16.0), Verdict::kGain) << on_witness.evidence();
  EXPECT_EQ(on_reading.verdict(16.0), Verdict::kUndecided) << on_reading.evidence();
  EXPECT_EQ(on_reading.verdict_now(2.0), Verdict::kOffset) << on_reading.evidence();
}

TEST(GainOrOffset, ThePitchLagIsANuisanceNotAGain) {
  // GIVEN a pitch reference swinging 10 +- 2 deg at 0.27 Hz (the IPC), an actuator lagging it by 0.1 s and a
  // +1.5 deg sensor offset
  const double tau = 0.1, dt = 0.01;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.2);
  GainOrOffsetTest offset_test(1, false), gain_test(1, false), no_nuisance(1, false);
  for (int i = 0; i < 300; ++i) {
    const double t = i * dt, w = 2.0 * M_PI * 0.27;
    const double r = 10.0 + 2.0 * std::sin(w * t), rate = 2.0 * w * std::cos(w * t);
    const double lag = -tau * rate, n = noise(rng);
    offset_test.add(lag + 1.5 + n, r, rate);
    gain_test.add(lag + 0.2 * r + n, r, rate);  // gain 1.2
  }
  // THEN in 3 s the offset is an offset and the gain a gain of 1.2, the lag taken by the nuisance term
  EXPECT_EQ(offset_test.verdict(16.0), Verdict::kOffset) << offset_test.evidence();
  EXPECT_NEAR(offset_test.offset(), 1.5, 0.05);
  EXPECT_EQ(gain_test.verdict(16.0), Verdict::kGain) << gain_test.evidence();
  EXPECT_NEAR(gain_test.gain(), 1.2, 0.01);
  // AND each model returns the lag it took (minus the nuisance's coefficient), known to a few ms
  EXPECT_NEAR(-offset_test.nuisance(false).coefficient, tau, 0.01);
  EXPECT_NEAR(-gain_test.nuisance(true).coefficient, tau, 0.01);
  EXPECT_LT(offset_test.nuisance(false).standard_error, 0.01);
  EXPECT_LT(gain_test.nuisance(true).standard_error, 0.01);
}

TEST(GainOrOffset, ALagIsUnknownWhereTheReferenceStoodStill) {
  // GIVEN a pitch reference standing at 0 deg (fine pitch, region 2) with rate noise of 1e-4 deg/s, and a
  // +1.5 deg sensor offset read with 0.2 deg noise
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.2), rate_noise(0.0, 1e-4);
  GainOrOffsetTest test(1, true);
  for (int i = 0; i < 500; ++i) test.add(1.5 + noise(rng), 1.5, rate_noise(rng));
  // THEN whatever lag it fits, its standard error is larger than any actuator's lag: it says nothing
  EXPECT_GT(test.nuisance(false).standard_error, 10.0) << -test.nuisance(false).coefficient;
  // AND with no record it is unknown too
  EXPECT_TRUE(std::isinf(GainOrOffsetTest(1, true).nuisance(false).standard_error));
}

TEST(GainOrOffset, AtZeroTheOnlyFitIsTheOffsetAndRestartForgets) {
  // GIVEN a pitch at fine pitch (reference 0 deg) read with a +2 deg offset
  GainOrOffsetTest test(1, false);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.2);
  for (int i = 0; i < 200; ++i) test.add(2.0 + noise(rng), 0.0);
  // THEN no gain can make it: an offset
  EXPECT_EQ(test.verdict(16.0), Verdict::kOffset);
  EXPECT_EQ(test.blocks(), 200);
  // AND a restart forgets it all
  test.restart();
  EXPECT_EQ(test.blocks(), 0);
  EXPECT_EQ(test.evidence(), 0.0);
  EXPECT_EQ(test.verdict(16.0), Verdict::kUndecided);
}

TEST(GainOrOffset, AFewBlocksDecideNothingByChance) {
  // GIVEN 4000 records of a rotor speed's gain of 1.1 at a steady 2.2 rad/s (0.01 rad/s of wander between 0.5
  // s blocks, 0.003 rad/s of witness error per block), each 4-8 blocks long: two to four seconds after an
  // onset, where the noise variance comes from one to five degrees of freedom
  std::mt19937_64 rng(11);
  std::normal_distribution<double> wander(0.0, 0.01), witness_error(0.0, 0.003);
  int decided_ratio = 0, decided_small_sample = 0;
  for (int r = 0; r < 4000; ++r) {
    GainOrOffsetTest ratio(1, false, false), small_sample(1, false, true);
    const int blocks = 4 + r % 5;
    for (int i = 0; i < blocks; ++i) {
      const double x = 2.2 + wander(rng), e = 0.1 * x + witness_error(rng);
      ratio.add(e, x);
      small_sample.add(e, x);
    }
    decided_ratio += ratio.verdict(16.0) != Verdict::kUndecided;
    decided_small_sample += small_sample.verdict(16.0) != Verdict::kUndecided;
  }
  // THEN the ratio itself, read as a chi-square(1) value, decides more than 0.5 % of them either way (80
  // times what a chi-square at 16 would: 1 in 16 000); taken at the F statistic's tail probability, none is
  // decided
  EXPECT_GT(decided_ratio, 20);
  EXPECT_EQ(decided_small_sample, 0);
}

TEST(GainOrOffset, ALongRecordKeepsItsVerdict) {
  // GIVEN the generator speed's gains of 0.995, 0.99 and 0.98 on a swinging quantity over 10 s, 1000 blocks
  const auto record = [](double gain, bool small_sample) {
    Quantity q{160.0, 3.0, 0.5};
    GainOrOffsetTest test(1, true, small_sample);
    for (int i = 0; i < 1000; ++i) {
      const double y = gain * q.at(i) + 0.1 * q.noisy(), w = q.at(i) + q.noisy();
      test.add(y - w, y);
    }
    return test;
  };
  for (const double gain : {0.995, 0.99, 0.98}) {
    const GainOrOffsetTest ratio = record(gain, false), small_sample = record(gain, true);
    // THEN with 997 degrees of freedom both decide alike, and near the threshold the F statistic's chi-square
    // value is the ratio's within 1 %
    EXPECT_EQ(small_sample.verdict(16.0), ratio.verdict(16.0)) << gain << ": " << ratio.evidence();
    EXPECT_LE(small_sample.evidence(), ratio.evidence());
    if (ratio.evidence() < 40.0) {
      EXPECT_NEAR(small_sample.evidence() / ratio.evidence(), 1.0, 0.01) << gain;
    }
  }
}

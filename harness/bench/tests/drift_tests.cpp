// Tests for harness/drift: the drift policy with a synthetic machine whose speed the test changes.
#include <gtest/gtest.h>

#include <vector>

#include "harness/bench/drift.hpp"

namespace {

// A machine whose calibration takes 2 ms times its slowness; each probe call is recorded.
struct FakeMachine {
  double slowness = 1.0;
  int probes = 0;
  vs::CalibrationSample measure() {
    ++probes;
    return {2.0 * slowness, 2.0 * slowness};
  }
};

vs::DriftGuard guardOn(FakeMachine& machine, vs::DriftPolicy policy = {}) {
  return vs::DriftGuard([&machine] { return machine.measure(); }, policy);
}

}  // namespace

TEST(DriftTest, ChangeIsTheLargerOfTheTwoWorkloadsInPercent) {
  EXPECT_DOUBLE_EQ(vs::calibrationChangePct({2.0, 4.0}, {2.0, 5.0}), 25.0);
  EXPECT_DOUBLE_EQ(vs::calibrationChangePct({2.0, 4.0}, {1.0, 4.0}), 50.0);
  EXPECT_DOUBLE_EQ(vs::calibrationChangePct({0.0, 0.0}, {1.0, 4.0}), 0.0);  // no time: no division
}

TEST(DriftTest, ASteadyMachineRunsEachRoundOnceBetweenCalibrations) {
  FakeMachine machine;
  vs::DriftGuard guard = guardOn(machine);
  int attempts = 0;
  for (int round = 0; round < 3; ++round) {
    vs::GuardedRound r = guard.run([&](int) {
      ++attempts;
      return true;
    });
    EXPECT_EQ(r.retries, 0);
    EXPECT_FALSE(r.disturbed);
    EXPECT_DOUBLE_EQ(r.driftPct, 0.0);
  }
  EXPECT_EQ(attempts, 3);
  EXPECT_EQ(machine.probes, 6);  // before the first round (three, their median) and after every round
  EXPECT_EQ(guard.history().size(), 4u);
  EXPECT_FALSE(guard.takeFirstWarning());
}

TEST(DriftTest, ARoundDuringWhichTheMachineSlowedIsDetectedAndRepeated) {
  FakeMachine machine;
  vs::DriftGuard guard = guardOn(machine);
  std::vector<int> attempts;
  // A slow phase starts during the first attempt and ends during the second: both attempts'
  // calibrations moved by 50 %; the third runs on a steady machine and is kept.
  vs::GuardedRound r = guard.run([&](int attempt) {
    attempts.push_back(attempt);
    if (attempt == 0) machine.slowness = 1.5;
    if (attempt == 1) machine.slowness = 1.0;
    return true;
  });
  EXPECT_EQ(attempts, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(r.retries, 2);
  EXPECT_FALSE(r.disturbed);
  EXPECT_DOUBLE_EQ(r.driftPct, 0.0);
  EXPECT_EQ(guard.disturbedRounds(), 2);
  EXPECT_EQ(guard.retries(), 2);
  EXPECT_TRUE(guard.takeFirstWarning());
  EXPECT_NEAR(guard.firstDisturbancePct(), 50.0, 1e-9);  // the move that set it off
  EXPECT_FALSE(guard.takeFirstWarning());  // the console warns once
}

TEST(DriftTest, RetriesAreBoundedAndTheKeptRoundSaysItIsDisturbed) {
  FakeMachine machine;
  vs::DriftGuard guard = guardOn(machine, {15.0, 2, true});
  int attempts = 0;
  vs::GuardedRound r = guard.run([&](int) {
    ++attempts;
    machine.slowness = machine.slowness > 1.0 ? 1.0 : 1.4;  // every round sees the speed move by 40 %
    return true;
  });
  EXPECT_EQ(attempts, 3);
  EXPECT_EQ(r.retries, 2);
  EXPECT_TRUE(r.disturbed);
  EXPECT_NEAR(r.driftPct, 40.0, 1e-9);

  vs::RowDrift row;
  row.add(r);
  EXPECT_TRUE(row.disturbed);
  EXPECT_EQ(row.retries, 2);
}

TEST(DriftTest, AMachineThatStaysSlowIsMarkedButNotRepeatedForever) {
  FakeMachine machine;
  vs::DriftGuard guard = guardOn(machine);
  guard.run([](int) { return true; });  // the run's first calibration: 2 ms
  int attempts = 0;
  vs::GuardedRound r = guard.run([&](int) {
    ++attempts;
    machine.slowness = 2.0;  // the machine halves its speed during the round, for good
    return true;
  });
  // The first attempt drifted and is repeated; the repeat ran at one speed (drift 0) but 100 % from
  // the run's first calibration: repeating again would not help, so it is kept and marked.
  EXPECT_EQ(attempts, 2);
  EXPECT_EQ(r.retries, 1);
  EXPECT_DOUBLE_EQ(r.driftPct, 0.0);
  EXPECT_NEAR(r.shiftPct, 100.0, 1e-9);
  EXPECT_TRUE(r.disturbed);
}

TEST(DriftTest, ARoundThatTimedNothingIsNotRepeated) {
  FakeMachine machine;
  vs::DriftGuard guard = guardOn(machine);
  int attempts = 0;
  vs::GuardedRound r = guard.run([&](int) {
    ++attempts;
    machine.slowness = 3.0;
    return false;  // the row failed: nothing was timed
  });
  EXPECT_EQ(attempts, 1);
  EXPECT_FALSE(r.disturbed);
  EXPECT_EQ(machine.probes, 3);  // the first calibration, none after a round that timed nothing
}

TEST(DriftTest, ADisabledCheckNeverCalibrates) {
  FakeMachine machine;
  vs::DriftGuard guard = guardOn(machine, {15.0, 2, false});
  int attempts = 0;
  guard.run([&](int) {
    ++attempts;
    machine.slowness *= 2.0;
    return true;
  });
  EXPECT_EQ(attempts, 1);
  EXPECT_EQ(machine.probes, 0);
}

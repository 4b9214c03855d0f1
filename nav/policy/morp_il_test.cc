#include "nav/policy/morp_il.h"

#include <array>
#include <memory>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "nav/policy/local_navigator.h"
#include "testing/navigator_steps.h"

namespace corridor::nav {
namespace {

using testing::FiveMetresEast;
using testing::TenLanes;

// A network that answers `linear` and `angular` (scaled outputs) whatever it is shown.
std::shared_ptr<const Mlp> ConstantNetwork(float linear, float angular) {
  DenseLayer layer{Eigen::MatrixXf::Zero(2, 48), Eigen::Vector2f(linear, angular), Activation::kIdentity};
  return std::make_shared<const Mlp>(std::vector<DenseLayer>{layer});
}

TEST(MorpIlFeaturesTest, EachStepIsLanesCommandGoalAndApproachOldestFirst) {
  MorpIlOptions options;
  MorpIlFeatures features(options);
  EXPECT_EQ(features.size(), 48);
  EXPECT_EQ(features.Input(), Eigen::VectorXf::Zero(48));
  // Lane 0 (leftmost) blocked at 1.5 m of the 3 m range; lane 9 blind; 10 lanes in 7 bins by index.
  std::vector<LaneResult> lanes = TenLanes({{0, 1.5}});
  lanes[9].blind = true;
  features.Push(lanes, std::numbers::pi / 2, 1.0, false, Twist2{0.13, -0.75});
  const Eigen::VectorXf first = features.Input();
  // Before four steps the first is repeated.
  for (int s = 0; s < 4; ++s) EXPECT_EQ(first.segment<12>(12 * s), first.head<12>());
  EXPECT_FLOAT_EQ(first(0), 0.5F);   // the left bin: the nearest dead-end over the range
  EXPECT_FLOAT_EQ(first(3), 1.0F);   // free
  EXPECT_FLOAT_EQ(first(6), 0.0F);   // the right bin: blind
  EXPECT_FLOAT_EQ(first(7), 0.5F);   // 0.13 of 0.26 m/s
  EXPECT_FLOAT_EQ(first(8), -0.5F);  // -0.75 of 1.5 rad/s
  EXPECT_FLOAT_EQ(first(9), 0.5F);   // the goal to the left: pi/2 over pi
  EXPECT_FLOAT_EQ(first(10), 0.5F);  // 1 m of the 2 m range
  EXPECT_FLOAT_EQ(first(11), 0.0F);
  features.Push(TenLanes(), 0.0, 9.0, true, Twist2{});
  const Eigen::VectorXf second = features.Input();
  EXPECT_EQ(second.segment<12>(24), first.head<12>());  // three steps of the first, then the newest
  EXPECT_FLOAT_EQ(second(36), 1.0F);
  EXPECT_FLOAT_EQ(second(46), 1.0F);  // the distance is capped
  EXPECT_FLOAT_EQ(second(47), 1.0F);  // the final approach
  for (int i = 0; i < 5; ++i) features.Push(TenLanes(), 0.0, 9.0, true, Twist2{});
  EXPECT_FLOAT_EQ(features.Input()(0), 1.0F);  // the first has gone out of the history
  features.Push({}, 0.0, 1.0, false, Twist2{});
  EXPECT_FLOAT_EQ(features.Input()(36), 0.0F);  // nothing seen: all blind
  EXPECT_THROW(MorpIlFeatures(MorpIlOptions{0}), std::invalid_argument);
}

TEST(MorpIlTest, TheNetworksOutputIsScaledAndKeptWithinTheLimits) {
  MorpIlOptions options;
  EXPECT_NEAR(MorpIlCommand(*ConstantNetwork(0.5F, -0.25F), Eigen::VectorXf::Zero(48), options).linear_mps, 0.13, 1e-6);
  EXPECT_NEAR(MorpIlCommand(*ConstantNetwork(0.5F, -0.25F), Eigen::VectorXf::Zero(48), options).angular_rps, -0.375,
              1e-6);
  const Twist2 wild = MorpIlCommand(*ConstantNetwork(7.0F, std::nanf("")), Eigen::VectorXf::Zero(48), options);
  EXPECT_DOUBLE_EQ(wild.linear_mps, 0.26);
  EXPECT_DOUBLE_EQ(wild.angular_rps, 0.0);
  EXPECT_NO_THROW(CheckMorpIlNetwork(*ConstantNetwork(0.0F, 0.0F), options));
  options.history = 3;
  EXPECT_THROW(CheckMorpIlNetwork(*ConstantNetwork(0.0F, 0.0F), options), std::invalid_argument);
}

TEST(MorpIlTest, TheNavigatorDrivesWithTheNetworkButNoFasterThanItCanStop) {
  LocalNavigatorOptions options;
  options.learned = ConstantNetwork(1.0F, 0.2F);
  LocalNavigator navigator(options);
  navigator.SetPath(FiveMetresEast());
  const LocalStep free = navigator.Update(Pose2{}, TenLanes(), 1.0, 0.05);
  EXPECT_TRUE(free.learned);
  EXPECT_NEAR(free.twist.linear_mps, options.il.max_linear_mps, 1e-9);
  EXPECT_NEAR(free.twist.angular_rps, 0.2 * options.il.max_angular_rps, 1e-6);
  // Something right in front: whatever the network says, the robot does not drive into it.
  const LocalStep blocked = navigator.Update(Pose2{}, TenLanes({{4, 0.25}, {5, 0.25}}), 1.0, 0.05);
  EXPECT_TRUE(blocked.learned);
  EXPECT_LE(blocked.twist.linear_mps, 0.0);
  // The mission's limit holds too.
  const LocalStep slow = navigator.Update(Pose2{}, TenLanes(), 0.1, 0.05);
  EXPECT_LE(slow.twist.linear_mps, 0.1 + 1e-9);
  options.il.history = 2;
  EXPECT_THROW(LocalNavigator{options}, std::invalid_argument);  // a network for another history
}

TEST(MorpIlTest, WhileTrainingEveryStepIsRecordedWithTheRulesCommandAndTheMixDecidesWhoDrives) {
  LocalNavigatorOptions options;
  options.il.max_linear_mps = options.follower.max_linear_mps;  // as the configuration sets them
  options.il.max_angular_rps = options.follower.max_angular_rps;
  options.teach = std::make_shared<Demonstrations>();
  LocalNavigator rules(options);  // no network: the rules drive, and teach
  rules.SetPath(FiveMetresEast());
  std::vector<Twist2> given;
  for (int i = 0; i < 5; ++i) given.push_back(rules.Update(Pose2{0.02 * i, 0.0, 0.0}, TenLanes(), 1.0, 0.05).twist);
  const Examples recorded = options.teach->Take(48);
  ASSERT_EQ(recorded.size(), 5);
  for (int i = 0; i < 5; ++i) {
    EXPECT_FLOAT_EQ(recorded.targets(0, i),
                    static_cast<float>(given[static_cast<std::size_t>(i)].linear_mps / options.il.max_linear_mps));
  }
  // Each step's input holds the command given after the step before.
  EXPECT_GT(given[2].linear_mps, 0.0);
  EXPECT_FLOAT_EQ(recorded.inputs(43, 3), static_cast<float>(given[2].linear_mps / options.il.max_linear_mps));
  EXPECT_TRUE(options.teach->inputs.empty());

  // With a network and beta 0.5, about half the steps are the network's (it answers a backward crawl).
  options.learned = ConstantNetwork(-0.1F, 0.0F);
  options.teach->beta = 0.5;
  LocalNavigator mixed(options);
  mixed.SetPath(FiveMetresEast());
  int learned = 0;
  for (int i = 0; i < 400; ++i) learned += mixed.Update(Pose2{}, TenLanes(), 1.0, 0.05).learned ? 1 : 0;
  EXPECT_GT(learned, 150);
  EXPECT_LT(learned, 250);
  const Examples mixed_steps = options.teach->Take(48);
  ASSERT_EQ(mixed_steps.size(), 400);
  EXPECT_GT(mixed_steps.targets.row(0).minCoeff(), 0.0F);  // labelled with the rules' forward command throughout
}

TEST(MorpIlTest, TheLastStretchToAWaypointIsThePoseControllersAndEndsWithinItsTolerance) {
  LocalNavigatorOptions options;
  options.learned = ConstantNetwork(1.0F, 1.0F);  // full speed, turning hard left: it would circle the goal for ever
  LocalNavigator navigator(options);
  navigator.SetPath(FiveMetresEast());
  Pose2 robot{4.6, 0.05, 0.1};  // within approach_m of the goal
  LocalStep step;
  const double dt = 0.05;
  for (int i = 0; i < 400 && !step.done; ++i) {
    step = navigator.Update(robot, TenLanes(), 1.0, dt);
    EXPECT_FALSE(step.learned);
    robot = robot * Pose2{step.twist.linear_mps * dt, 0.0, step.twist.angular_rps * dt};
  }
  ASSERT_TRUE(step.done);
  EXPECT_LE((robot.translation() - Eigen::Vector2d(5.0, 0.0)).norm(), options.follower.position_tolerance_m * 5.0);
}

}  // namespace
}  // namespace corridor::nav

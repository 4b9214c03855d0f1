#include "nav/policy/takiguchi.h"

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "nav/policy/local_navigator.h"
#include "testing/navigator_steps.h"

namespace corridor::nav {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kAhead = 45;  // of 91 rays, right to left
constexpr int kLeft = 90;

TrackedObject RayObject(const Eigen::Vector2d& position, const Eigen::Vector2d& velocity, double radius_m = 0.3) {
  TrackedObject o;
  o.position = position;
  o.velocity = velocity;
  o.radius_m = radius_m;
  o.moving = velocity.norm() > 0.0;
  return o;
}

TEST(TakiguchiInputTest, RaysShowDistanceSpeedAndWayOfWhatIsAroundAndTheGoalComesLast) {
  const TakiguchiOptions options;
  EXPECT_EQ(TakiguchiInputs(options), 274);
  EXPECT_EQ(TakiguchiClasses(options), 20);
  // The robot at (1, 1) facing +y: world (1, 3) is 2 m straight ahead.
  const Pose2 robot{1.0, 1.0, kPi / 2};
  Surroundings nothing;
  const Eigen::VectorXf empty = TakiguchiInput(robot, nothing, -kPi / 4, options);
  ASSERT_EQ(empty.size(), 274);
  EXPECT_EQ(empty.head(91), Eigen::VectorXf::Ones(91));
  EXPECT_EQ(empty.segment(91, 182), Eigen::VectorXf::Zero(182));
  EXPECT_FLOAT_EQ(empty(273), -0.25F);

  Surroundings walking;
  walking.objects.push_back(RayObject({1.0, 3.0}, {0.0, -0.75}));  // walking straight at the robot
  const Eigen::VectorXf at = TakiguchiInput(robot, walking, 0.0, options);
  EXPECT_NEAR(at(kAhead), (2.0 - 0.3) / 5.0, 1e-6);
  EXPECT_NEAR(at(91 + kAhead), 0.5, 1e-6);
  EXPECT_NEAR(at(182 + kAhead), 0.0, 1e-6);
  EXPECT_FLOAT_EQ(at(0), 1.0F);  // nothing to the right
  EXPECT_FLOAT_EQ(at(kLeft), 1.0F);
  // The same person crossing to the robot's right (world +x): a quarter turn from coming at it.
  walking.objects[0].velocity = {0.75, 0.0};
  EXPECT_NEAR(TakiguchiInput(robot, walking, 0.0, options)(182 + kAhead), 0.5, 1e-6);
  // Walking away: the cut at +-1, where it matters least.
  walking.objects[0].velocity = {0.0, 0.75};
  EXPECT_NEAR(std::abs(TakiguchiInput(robot, walking, 0.0, options)(182 + kAhead)), 1.0, 1e-6);

  // A wall's points to the left stand still; something behind the robot is not on any ray, even straddling the
  // cut at +-pi.
  Surroundings still;
  still.static_points.push_back(robot.Transform({0.0, 1.5}));
  still.objects.push_back(RayObject(robot.Transform({-0.5, -0.05}), Eigen::Vector2d::Zero(), 0.45));
  const Eigen::VectorXf side = TakiguchiInput(robot, still, 0.0, options);
  EXPECT_NEAR(side(kLeft), (1.5 - options.point_radius_m) / 5.0, 1e-6);
  EXPECT_FLOAT_EQ(side(91 + kLeft), 0.0F);
  for (int i = 0; i < 91; ++i) {
    if (i != kLeft && i != kLeft - 1) {
      EXPECT_FLOAT_EQ(side(i), 1.0F) << "ray " << i;
    }
  }
  // A large object beside the robot, its centre behind it, still reaches the ray to the left.
  still.objects.push_back(RayObject(robot.Transform({-0.5, 0.45}), Eigen::Vector2d::Zero(), 0.55));
  EXPECT_LT(TakiguchiInput(robot, still, 0.0, options)(kLeft), 0.1F);
  // Inside an object: every ray toward it meets it at once.
  Surroundings inside;
  inside.objects.push_back(RayObject(robot.Transform({0.1, 0.0}), Eigen::Vector2d::Zero(), 0.3));
  EXPECT_FLOAT_EQ(TakiguchiInput(robot, inside, 0.0, options)(kAhead), 0.0F);
}

TEST(TakiguchiInputTest, AllRoundRaysStartStraightBehindAndSeeWhatIsThere) {
  TakiguchiOptions options;
  options.rays = 180;  // every 2 degrees from straight behind, round by the right
  options.field_rad = 2.0 * kPi;
  ASSERT_NO_THROW(CheckTakiguchiOptions(options));
  EXPECT_EQ(TakiguchiInputs(options), 541);
  const Pose2 robot{1.0, 1.0, kPi / 2};
  // Someone 2 m behind, walking at the robot: straddles the cut at +-pi, so the first ray and the last both meet it.
  Surroundings behind;
  behind.objects.push_back(RayObject(robot.Transform({-2.0, 0.0}), Eigen::Vector2d(0.0, 0.75)));
  const Eigen::VectorXf at = TakiguchiInput(robot, behind, 0.0, options);
  EXPECT_NEAR(at(0), (2.0 - 0.3) / 5.0, 1e-6);
  EXPECT_LT(at(179), 0.4F);
  EXPECT_NEAR(at(180), 0.5, 1e-6);  // its speed
  EXPECT_NEAR(at(360), 0.0, 1e-6);  // coming straight down the ray
  EXPECT_FLOAT_EQ(at(90), 1.0F);    // nothing ahead
  // Ahead (ray 90) and to the left (ray 135) as the front-half rays see them.
  Surroundings ahead;
  ahead.objects.push_back(RayObject(robot.Transform({2.0, 0.0}), Eigen::Vector2d::Zero()));
  ahead.static_points.push_back(robot.Transform({0.0, 1.5}));
  const Eigen::VectorXf front = TakiguchiInput(robot, ahead, 0.0, options);
  EXPECT_NEAR(front(90), (2.0 - 0.3) / 5.0, 1e-6);
  EXPECT_NEAR(front(135), (1.5 - options.point_radius_m) / 5.0, 1e-6);
  EXPECT_FLOAT_EQ(front(0), 1.0F);
  options.field_rad = 2.0 * kPi + 0.1;
  EXPECT_THROW(CheckTakiguchiOptions(options), std::invalid_argument);
}

TEST(TakiguchiCommandTest, ClassesAreHeadingsFromRightToLeftThenStop) {
  const TakiguchiOptions options;
  EXPECT_NEAR(*TakiguchiHeading(0, options), -kPi / 2, 1e-12);
  EXPECT_NEAR(*TakiguchiHeading(9, options), 0.0, 1e-12);
  EXPECT_NEAR(*TakiguchiHeading(18, options), kPi / 2, 1e-12);
  EXPECT_FALSE(TakiguchiHeading(19, options));
  EXPECT_THROW(TakiguchiHeading(20, options), std::out_of_range);
  EXPECT_THROW(TakiguchiHeading(-1, options), std::out_of_range);
  // Straight on at full speed; a heading to the side turns on the spot; stop stops.
  EXPECT_DOUBLE_EQ(TakiguchiCommand(9, options).linear_mps, options.max_linear_mps);
  EXPECT_DOUBLE_EQ(TakiguchiCommand(9, options).angular_rps, 0.0);
  const Twist2 slight = TakiguchiCommand(11, options);  // 20 degrees left
  EXPECT_NEAR(slight.linear_mps, options.max_linear_mps * std::cos(kPi / 9), 1e-12);
  EXPECT_NEAR(slight.angular_rps, options.k_heading * kPi / 9, 1e-12);
  EXPECT_DOUBLE_EQ(TakiguchiCommand(0, options).linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(TakiguchiCommand(0, options).angular_rps, -options.max_angular_rps);
  EXPECT_DOUBLE_EQ(TakiguchiCommand(19, options).linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(TakiguchiCommand(19, options).angular_rps, 0.0);
  TakiguchiOptions bad;
  bad.rays = 1;
  EXPECT_THROW(CheckTakiguchiOptions(bad), std::invalid_argument);
  EXPECT_NO_THROW(CheckTakiguchiOptions(options));
}

TEST(SafeDirectionTest, EachChoiceIsDrivenAsTheHeadingControllerDrivesIt) {
  const TakiguchiOptions options;
  const SafeDirectionOptions safe;
  const Pose2 robot{1.0, 2.0, 0.0};
  const std::vector<Eigen::Vector2d> straight = DriveClass(robot, 9, options, safe);
  ASSERT_EQ(straight.size(), 30U);
  EXPECT_NEAR(straight.back().x(), 1.0 + 0.26 * 3.0, 1e-9);
  EXPECT_NEAR(straight.back().y(), 2.0, 1e-9);
  // A quarter turn to the left: on the spot first, then along it.
  const std::vector<Eigen::Vector2d> left = DriveClass(robot, 18, options, safe);
  EXPECT_EQ(left.front(), robot.translation());
  EXPECT_GT(left.back().y(), 2.4);
  EXPECT_LT(std::abs(left.back().x() - 1.0), 0.2);
  for (const Eigen::Vector2d& p : DriveClass(robot, 19, options, safe)) EXPECT_EQ(p, robot.translation());
}

TEST(SafeDirectionTest, TimeToMeetIsWhenTheRobotComesWithinReachClosingIn) {
  const TakiguchiOptions options;
  const SafeDirectionOptions safe;  // 0.2 + 0.25 + 0.1 = 0.55 m apart at contact
  const Pose2 robot;
  const std::vector<Eigen::Vector2d> straight = DriveClass(robot, 9, options, safe);
  const double inf = std::numeric_limits<double>::infinity();
  // Head on, closing at 1.06 m/s from 3 m: within reach at 2.31 s, the first step after it.
  EXPECT_NEAR(TimeToMeet({0.0, 0.0}, straight, DiscMover{{3.0, 0.0}, {-0.8, 0.0}, 0.25}, safe), 2.4, 1e-9);
  EXPECT_EQ(TimeToMeet({0.0, 0.0}, straight, DiscMover{{3.0, 0.0}, {0.8, 0.0}, 0.25}, safe), inf);
  EXPECT_EQ(TimeToMeet({0.0, 0.0}, straight, DiscMover{{3.0, 1.0}, {0.0, 0.0}, 0.25}, safe), inf);
  // Within reach already: meeting when closing in, not when standing or getting away.
  const DiscMover touching{{0.4, 0.0}, {0.0, 0.0}, 0.25};
  EXPECT_NEAR(TimeToMeet({0.0, 0.0}, straight, touching, safe), 0.1, 1e-9);
  EXPECT_EQ(TimeToMeet({0.0, 0.0}, DriveClass(robot, 19, options, safe), touching, safe), inf);
  // Turning away on the spot does not close in; the arc after the turn still sweeps toward it, later.
  EXPECT_GT(TimeToMeet({0.0, 0.0}, DriveClass(robot, 0, options, safe), touching, safe), 0.3);
}

TEST(SafeDirectionTest, TheExpertHeadsForTheGoalAndStepsAsideOrWaitsForPeople) {
  const TakiguchiOptions options;
  const SafeDirectionOptions safe;
  const Pose2 robot{2.0, -1.0, kPi};  // facing -x
  // Nothing around: the heading nearest the goal; a goal behind turns the robot toward its side.
  EXPECT_EQ(SafeDirectionLabel(robot, {}, 0.0, options, safe), 9);
  EXPECT_EQ(SafeDirectionLabel(robot, {}, 32.0 * kPi / 180, options, safe), 12);
  EXPECT_EQ(SafeDirectionLabel(robot, {}, 3.0, options, safe), 18);
  EXPECT_EQ(SafeDirectionLabel(robot, {}, -3.0, options, safe), 0);
  // Someone walking straight at the robot 2.5 m ahead: straight on and standing still both meet them within the
  // horizon; the robot steps aside at 80 degrees (the least that keeps clear once it has turned), to its right of
  // equals.
  const std::vector<DiscMover> oncoming{{robot.Transform({2.5, 0.0}), Eigen::Vector2d(0.8, 0.0), 0.25}};
  EXPECT_EQ(SafeDirectionLabel(robot, oncoming, 0.0, options, safe), 1);
  // Someone crossing from the left 0.6 m ahead: waiting lets them pass (keeping clear of them otherwise takes a
  // detour of 80 degrees or more).
  const std::vector<DiscMover> crossing{{robot.Transform({0.6, 1.0}), Eigen::Vector2d(0.0, 0.8), 0.25}};
  EXPECT_EQ(SafeDirectionLabel(robot, crossing, 0.0, options, safe), 19);
  // A wall across the way 0.45 m ahead: along it to the goal's side beats standing still only when the goal is
  // beside the robot.
  std::vector<DiscMover> wall;
  for (int i = -40; i <= 40; ++i) wall.push_back({robot.Transform({0.45, 0.05 * i}), Eigen::Vector2d::Zero(), 0.05});
  EXPECT_EQ(SafeDirectionLabel(robot, wall, 0.0, options, safe), 19);
  EXPECT_EQ(SafeDirectionLabel(robot, wall, 1.4, options, safe), 18);
}

TEST(SafeDirectionTest, MoversAroundAreTheTrackersObjectsAndPointsWithinReach) {
  const TakiguchiOptions options;
  Surroundings around;
  around.objects.push_back(RayObject({1.0, 0.0}, {0.5, 0.0}, 0.1));
  around.objects.push_back(RayObject({9.0, 0.0}, {0.5, 0.0}));
  around.static_points = {{0.0, 1.0}, {0.0, 8.0}};
  const std::vector<DiscMover> movers = MoversAround({0.0, 0.0}, around, 3.0, options);
  ASSERT_EQ(movers.size(), 2U);
  EXPECT_DOUBLE_EQ(movers[0].radius_m, options.min_object_radius_m);
  EXPECT_EQ(movers[0].velocity, Eigen::Vector2d(0.5, 0.0));
  EXPECT_EQ(movers[1].velocity, Eigen::Vector2d::Zero());
  EXPECT_DOUBLE_EQ(movers[1].radius_m, options.point_radius_m);
}

// A network answering `klass` whatever it is shown.
std::shared_ptr<const Mlp> Always(int klass) {
  Eigen::VectorXf bias = Eigen::VectorXf::Zero(20);
  bias(klass) = 5.0F;
  return std::make_shared<const Mlp>(
      std::vector<DenseLayer>{{Eigen::MatrixXf::Zero(20, 274), bias, Activation::kSoftmax}});
}

TEST(TakiguchiPolicyTest, TheNavigatorDrivesTheNetworksHeadingAndTheExpertTeachesWithoutOne) {
  LocalNavigatorOptions options;
  options.direction_policy = true;
  EXPECT_THROW(LocalNavigator{options}, std::invalid_argument);  // neither a network nor training
  options.direction = Always(13);                                // 40 degrees to the left
  LocalNavigator driven(options);
  driven.SetPath(testing::FiveMetresEast());
  Surroundings around;
  const LocalStep step = driven.Update(Pose2{}, testing::TenLanes(), 1.0, 0.05, &around);
  EXPECT_TRUE(step.learned);
  const Twist2 want = TakiguchiCommand(13, options.takiguchi);
  EXPECT_NEAR(step.twist.linear_mps, want.linear_mps, 1e-9);
  EXPECT_NEAR(step.twist.angular_rps, want.angular_rps, 1e-9);
  options.direction = Always(3);
  options.takiguchi.rays = 45;
  EXPECT_THROW(LocalNavigator{options}, std::invalid_argument);  // a network for other rays

  // Training without a network: the expert drives, and every step is its one-hot label. Someone walks straight at
  // the robot: it steps aside, and evasion does not take the command over.
  LocalNavigatorOptions teaching;
  teaching.direction_policy = true;
  teaching.teach = std::make_shared<Demonstrations>();
  LocalNavigator expert(teaching);
  expert.SetPath(testing::FiveMetresEast());
  around.objects.push_back(RayObject({2.5, 0.0}, {-0.8, 0.0}, 0.25));
  const LocalStep aside = expert.Update(Pose2{}, testing::TenLanes(), 1.0, 0.05, &around);
  EXPECT_FALSE(aside.learned);
  EXPECT_FALSE(aside.evading);
  const Examples recorded = teaching.teach->Take(274);
  ASSERT_EQ(recorded.size(), 1);
  ASSERT_EQ(recorded.targets.rows(), 20);
  EXPECT_EQ(recorded.targets.sum(), 1.0F);
  Eigen::Index label = 0;
  recorded.targets.col(0).maxCoeff(&label);
  EXPECT_NE(label, 9);  // not straight on
  EXPECT_NEAR(aside.twist.angular_rps, TakiguchiCommand(static_cast<int>(label), teaching.takiguchi).angular_rps, 1e-9);
}

}  // namespace
}  // namespace corridor::nav

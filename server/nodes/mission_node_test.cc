#include "server/nodes/mission_node.h"

#include <gtest/gtest.h>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// A mission across an empty 10 x 10 m room, driven on free lanes; the robot's pose is held still, so that what the
// mission remembers stays where it is.
class MissionNodeTest : public ::testing::Test {
 protected:
  explicit MissionNodeTest(const nav::MissionRunnerOptions& options = {})
      : executors_(clock_, Schedule::kLockstep),
        planner_(executors_.planning, bus_, nav::CostmapOptions{}),
        node_(executors_.control, bus_, planner_, options) {
    MapInUse room;
    room.name = "room";
    room.grid = std::make_shared<const nav::OccupancyGrid>(200, 200, 0.05, nav::Pose2{}, nav::kFreeCell);
    bus_.Get(topics::kMapInUse).Publish(std::move(room));
    node_.Activate();
    bus_.Get(topics::kPose).Publish(StampedPose{clock_.Now(), nav::Pose2{2.0, 5.0, 0.0}});
    nav::MissionGoal goal;
    goal.pose = {8.0, 5.0, 0.0};
    node_.Start({goal}, 0.5, [](const MissionState&) {});
    executors_.RunUntilIdle();
  }
  // One depth frame's lanes, free or (`wall`) each ending 0.3 m ahead; returns the mission's command that answers it.
  MissionCommand Frame(bool wall = false) {
    std::vector<nav::LaneResult> lanes;
    for (const double offset : {-0.15, -0.05, 0.05, 0.15}) {
      nav::LaneResult lane;
      lane.offset_m = offset;
      lane.free_distance_m = wall ? 0.3 : 4.0;
      lane.dead_end = wall;
      lane.point = {0.3, offset, 0.1};
      lanes.push_back(lane);
    }
    clock_.Set(clock_.Now() + drivers::FromSeconds(0.055));
    const drivers::TimeNs now = clock_.Now();
    bus_.Get(topics::kGroundLanes).Publish(GroundLanes{now, now, ++sequence_, 0.0, lanes, {}, {}, {}});
    executors_.RunUntilIdle();
    const auto command = bus_.Get(topics::kMissionCommand).latest();
    return command ? *command : MissionCommand{};
  }

  // The fastest forward command over `frames` frames.
  double FastestOver(int frames) {
    double fastest = -1.0;
    for (int i = 0; i < frames; ++i) fastest = std::max(fastest, Frame().twist.linear_mps);
    return fastest;
  }

  drivers::ManualClock clock_;
  Executors executors_;
  Bus bus_;
  PlannerService planner_;
  MissionNode node_;
  std::uint64_t sequence_ = 0;
};

TEST_F(MissionNodeTest, ABumpTheControlNodeReportsIsRememberedOnTheSideTheBaseWasDriving) {
  ASSERT_GT(FastestOver(40), 0.1) << "the mission never drove forward";
  // Bumped while backing: something behind; forward stays free.
  bus_.Get(topics::kBumped).Publish(Bumped{clock_.Now(), true});
  EXPECT_GT(FastestOver(10), 0.1);
  // Bumped driving forward: something in front, seen or not; the mission no longer drives into it.
  bus_.Get(topics::kBumped).Publish(Bumped{clock_.Now(), false});
  EXPECT_LE(FastestOver(10), 0.0);
}

TEST_F(MissionNodeTest, AnOldBumpIsNotWhereTheRobotIsNow) {
  ASSERT_GT(FastestOver(40), 0.1) << "the mission never drove forward";
  bus_.Get(topics::kBumped).Publish(Bumped{clock_.Now() - drivers::FromSeconds(5.0), false});
  EXPECT_GT(FastestOver(10), 0.1);
}

// The same with a navigator that gives up on making headway after a second.
nav::MissionRunnerOptions QuicklyStuck() {
  nav::MissionRunnerOptions o;
  o.navigator.stuck_s = 1.0;
  return o;
}

class StuckMissionNodeTest : public MissionNodeTest {
 protected:
  StuckMissionNodeTest() : MissionNodeTest(QuicklyStuck()) {}
};

TEST_F(StuckMissionNodeTest, ARobotThatMakesNoHeadwayGetsAPathRoundWhatBlocksIt) {
  const auto farthest_off_the_line = [this] {
    const auto state = bus_.Get(topics::kMission).latest();
    double farthest = 0.0;
    if (state) {
      for (const nav::Pose2& p : state->path) {
        farthest = std::max(farthest, std::abs(p.y_m - 5.0));
      }
    }
    return farthest;
  };
  for (int i = 0; i < 10; ++i) Frame();
  ASSERT_LT(farthest_off_the_line(), 0.05) << "the first path goes straight across the room";
  // Something across the way 0.3 m in front of the robot, which is held still: after a second, a path round it.
  double farthest = 0.0;
  for (int i = 0; i < 60 && farthest < 0.3; ++i) {
    Frame(true);
    farthest = farthest_off_the_line();
  }
  EXPECT_GT(farthest, 0.3);
}

}  // namespace
}  // namespace corridor::server

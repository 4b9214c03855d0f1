#include "tools/scenario/scenario.h"

#include <gtest/gtest.h>

namespace corridor::scenario {
namespace {

// The CI scenario: one seeded run of the paper's protocol with people and unmapped obstacles. corridor's navigator
// must reach the goal without touching anything.
TEST(ScenarioTest, ASeededRunAmongPeopleAndObstaclesReachesItsGoalWithoutCollision) {
  ScenarioOptions options;
  options.seed = 7;
  options.pedestrians = 3;
  options.static_obstacles = 4;
  const Layout layout = MakeLayout(options, 0, 0);
  EXPECT_EQ(layout.routes.size(), 3u);
  EXPECT_EQ(layout.world.obstacles.size(), 4u);
  const double distance = (layout.goal - layout.start.translation()).norm();
  EXPECT_GE(distance, 7.0);
  EXPECT_LE(distance, 11.0);
  const RunResult result = RunOnce(layout, Policy::kMorpRb, options);
  EXPECT_EQ(ToString(result.outcome), std::string("success")) << result.collided_with;
  EXPECT_GT(result.depth_ms.size(), 50u);  // it drove on depth frames
}

TEST(ScenarioTest, TheSameSeedGivesTheSameScenario) {
  ScenarioOptions options;
  options.pedestrians = 2;
  options.static_obstacles = 2;
  const Layout a = MakeLayout(options, 3, 1);
  const Layout b = MakeLayout(options, 3, 1);
  EXPECT_EQ(a.goal, b.goal);
  EXPECT_EQ(a.start.translation(), b.start.translation());
  ASSERT_EQ(a.routes.size(), 2u);
  ASSERT_EQ(b.routes.size(), 2u);
  EXPECT_EQ(a.routes[0].start, b.routes[0].start);
  const Layout c = MakeLayout(options, 3, 2);
  EXPECT_NE(a.goal, c.goal);
}

}  // namespace
}  // namespace corridor::scenario

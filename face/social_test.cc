#include "face/social.h"

#include <cmath>

#include <gtest/gtest.h>

namespace corridor::face {
namespace {

using drivers::FromSeconds;

Detection Person(double x, double y, int track = 0) {
  return {"person", 0.9, std::nullopt, Eigen::Vector3d(x, y, 0.8), track, "sim"};
}

TEST(SocialSenseTest, NearInTheWayAndWhereTheEyesLook) {
  SocialSense sense;
  SocialCues c = sense.Update({Person(1.2, 0.3), Person(3.0, -1.0)}, 0.3, 0.0, 0);
  EXPECT_TRUE(c.near);
  EXPECT_FALSE(c.blocking);  // 1.24 m: near, not in the way
  EXPECT_TRUE(c.gaze_at_person);
  EXPECT_NEAR(c.gaze_rad, std::atan2(0.3, 1.2), 1e-9);
  c = sense.Update({Person(0.8, 0.1)}, 0.0, 0.0, FromSeconds(0.2));
  EXPECT_TRUE(c.blocking);
  // Beside the robot is neither near in front nor in the way; far away is only looked at.
  c = sense.Update({Person(0.1, 1.0), Person(3.5, 0.0)}, 0.0, 0.0, FromSeconds(0.4));
  EXPECT_FALSE(c.near);
  EXPECT_FALSE(c.blocking);
  EXPECT_TRUE(c.gaze_at_person);
  EXPECT_NEAR(c.gaze_rad, 0.7, 1e-9);  // the nearest, beside it, clamped to what the eyes can turn
}

TEST(SocialSenseTest, WithNobodyTheEyesLookIntoTheTurn) {
  SocialSense sense;
  SocialCues c = sense.Update({}, 0.4, 0.5, 0);
  EXPECT_FALSE(c.gaze_at_person);
  EXPECT_GT(c.gaze_rad, 0.5);  // turning left: looking left
  EXPECT_NEAR(sense.Update({}, 0.4, 0.0, 1).gaze_rad, 0.0, 1e-12);
}

TEST(SocialSenseTest, SomeoneStandingInFrontForTwoSecondsOrAFaceIsLookingAtTheRobot) {
  SocialSense sense;
  bool looking = false;
  for (int i = 0; i <= 9; ++i)
    looking = sense.Update({Person(1.0, 0.05 * (i % 2), 7)}, 0, 0, FromSeconds(0.2 * i)).looking;
  EXPECT_FALSE(looking);  // 1.8 s
  EXPECT_TRUE(sense.Update({Person(1.0, 0.0, 7)}, 0, 0, FromSeconds(2.0)).looking);
  // Walking past is not looking.
  SocialSense other;
  for (int i = 0; i <= 15; ++i)
    looking = other.Update({Person(1.0, -1.0 + 0.15 * i, 3)}, 0, 0, FromSeconds(0.2 * i)).looking;
  EXPECT_FALSE(looking);
  // A face turned to the robot within 2.5 m is looking at once.
  const Detection face{"face", 0.8, std::nullopt, Eigen::Vector3d(2.0, 0.2, 1.5), 0, "face_cascade"};
  EXPECT_TRUE(SocialSense().Update({face}, 0, 0, 0).looking);
}

}  // namespace
}  // namespace corridor::face

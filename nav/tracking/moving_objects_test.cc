#include "nav/tracking/moving_objects.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace corridor::nav {
namespace {

struct Disc {
  Eigen::Vector2d centre;
  double radius;
};

// A 360-beam scan from `sensor` (yaw 0) of discs inside a square room [0, size]^2, with range noise.
std::vector<float> Scan(const Eigen::Vector2d& sensor, const std::vector<Disc>& discs, double size, std::mt19937& rng,
                        double noise_m = 0.01) {
  std::normal_distribution<double> noise(0.0, noise_m);
  std::vector<float> ranges(360);
  for (int i = 0; i < 360; ++i) {
    const double a = -std::numbers::pi + i * std::numbers::pi / 180.0;
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    double best = std::numeric_limits<double>::infinity();
    // Walls.
    for (int axis = 0; axis < 2; ++axis) {
      if (std::abs(d[axis]) < 1e-12) continue;
      for (const double wall : {0.0, size}) {
        const double t = (wall - sensor[axis]) / d[axis];
        if (t > 0.0) best = std::min(best, t);
      }
    }
    for (const Disc& disc : discs) {
      const Eigen::Vector2d f = sensor - disc.centre;
      const double b = f.dot(d);
      const double c = f.squaredNorm() - disc.radius * disc.radius;
      const double h = b * b - c;
      if (h < 0.0) continue;
      const double t = -b - std::sqrt(h);
      if (t > 0.0) best = std::min(best, t);
    }
    ranges[i] = static_cast<float>(best + noise(rng));
  }
  return ranges;
}

// The world-frame points of a scan from Scan() taken at `sensor` (yaw 0).
std::vector<Eigen::Vector2d> ToWorld(const Eigen::Vector2d& sensor, const std::vector<float>& ranges) {
  return ScanToWorld({sensor.x(), sensor.y(), 0.0}, -std::numbers::pi, std::numbers::pi / 180.0, 0.1, 8.0, ranges);
}

OccupancyGrid Room(double size) {
  const double res = 0.05;
  const int n = static_cast<int>(std::round(size / res));
  OccupancyGrid grid(n + 2, n + 2, res, Pose2{-res, -res, 0.0}, kFreeCell);
  for (int i = 0; i < n + 2; ++i) {
    for (const int j : {0, 1, n, n + 1}) {
      grid.at({i, j}) = kOccupiedCell;
      grid.at({j, i}) = kOccupiedCell;
    }
  }
  return grid;
}

// Feeds `scans` scans at 10 Hz of a person walking at `velocity` from `start`, seen from a sensor moving at
// `sensor_velocity` from `sensor_start`; returns the tracker after the last one.
MovingObjectTracker Watch(const Eigen::Vector2d& start, const Eigen::Vector2d& velocity,
                          const Eigen::Vector2d& sensor_start, const Eigen::Vector2d& sensor_velocity, int scans,
                          std::mt19937& rng, double* last_t = nullptr) {
  MovingObjectTracker tracker{MovingObjectOptions{}};
  tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
  for (int k = 0; k < scans; ++k) {
    const double t = 0.1 * k;
    const Eigen::Vector2d sensor = sensor_start + t * sensor_velocity;
    const auto ranges = Scan(sensor, {{start + t * velocity, 0.25}}, 10.0, rng);
    tracker.Update(t, sensor, ToWorld(sensor, ranges));
    if (last_t != nullptr) *last_t = t;
  }
  return tracker;
}

TEST(MovingObjectTrackerTest, AWalkingPersonGetsItsVelocityAndTheWallsAreNotObjects) {
  std::mt19937 rng(7);
  double t = 0.0;
  const Eigen::Vector2d start(3.0, 6.0);
  const Eigen::Vector2d velocity(0.8, -0.3);
  const MovingObjectTracker tracker = Watch(start, velocity, {5.0, 3.0}, {0.0, 0.0}, 12, rng, &t);
  ASSERT_EQ(tracker.objects().size(), 1u);
  const TrackedObject& person = tracker.objects().front();
  EXPECT_TRUE(person.moving);
  EXPECT_NEAR(person.velocity.x(), velocity.x(), 0.08);
  EXPECT_NEAR(person.velocity.y(), velocity.y(), 0.08);
  // The laser sees the near side: the centroid is inside the person, toward the sensor.
  EXPECT_LT((person.position - (start + t * velocity)).norm(), 0.25);
  EXPECT_GT(person.radius_m, 0.1);
  EXPECT_LT(person.radius_m, 0.35);
  // The walls stay as static points; the person's points do not.
  EXPECT_GT(tracker.static_points().size(), 200u);
  for (const auto& p : tracker.static_points()) EXPECT_GT((p - (start + t * velocity)).norm(), 0.4);
}

TEST(MovingObjectTrackerTest, AStandingPersonIsAnObjectThatDoesNotMove) {
  std::mt19937 rng(8);
  const Eigen::Vector2d at(6.0, 6.0);
  const MovingObjectTracker tracker = Watch(at, {0.0, 0.0}, {3.0, 3.0}, {0.2, 0.0}, 12, rng);
  ASSERT_EQ(tracker.objects().size(), 1u);
  EXPECT_FALSE(tracker.objects().front().moving);
  EXPECT_EQ(tracker.objects().front().velocity, Eigen::Vector2d::Zero());
  std::size_t near = 0;
  for (const auto& p : tracker.static_points()) near += (p - at).norm() < 0.3 ? 1 : 0;
  EXPECT_GT(near, 5u);  // kept clear of like a wall
}

TEST(MovingObjectTrackerTest, VelocitiesHoldFromAMovingRobotInEveryDirection) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    const double heading = 2.0 * std::numbers::pi * unit(rng);
    const double speed = 0.3 + 0.9 * unit(rng);
    const Eigen::Vector2d velocity = speed * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    const Eigen::Vector2d start = Eigen::Vector2d(5.0, 5.0) - 0.5 * velocity;  // crosses the middle at t = 0.5 s
    const double robot_heading = 2.0 * std::numbers::pi * unit(rng);
    const Eigen::Vector2d sensor_start =
        Eigen::Vector2d(5.0, 5.0) + 1.5 * Eigen::Vector2d(std::cos(robot_heading), std::sin(robot_heading));
    const Eigen::Vector2d sensor_velocity = 0.26 * Eigen::Vector2d(-std::sin(robot_heading), std::cos(robot_heading));
    const MovingObjectTracker tracker = Watch(start, velocity, sensor_start, sensor_velocity, 11, rng);
    ASSERT_EQ(tracker.objects().size(), 1u) << "trial " << trial;
    const TrackedObject& person = tracker.objects().front();
    EXPECT_TRUE(person.moving) << "trial " << trial;
    EXPECT_LT((person.velocity - velocity).norm(), 0.15) << "trial " << trial << " speed " << speed;
  }
}

TEST(MovingObjectTrackerTest, TwoPeopleApartAreTwoObjectsAndATimeResetStartsAgain) {
  std::mt19937 rng(10);
  MovingObjectTracker tracker{MovingObjectOptions{}};
  tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
  const Eigen::Vector2d sensor(5.0, 2.0);
  const auto scan_at = [&](double t) {
    const auto ranges = Scan(sensor, {{{3.0 + 0.8 * t, 5.0}, 0.25}, {{7.0, 6.0 - 0.6 * t}, 0.25}}, 10.0, rng);
    return ToWorld(sensor, ranges);
  };
  for (int k = 0; k < 10; ++k) tracker.Update(0.1 * k, sensor, scan_at(0.1 * k));
  ASSERT_EQ(tracker.objects().size(), 2u);
  EXPECT_NEAR(tracker.objects()[0].velocity.x(), 0.8, 0.1);
  EXPECT_NEAR(tracker.objects()[1].velocity.y(), -0.6, 0.1);
  // A stamp from the past (a replayed log, a reset clock) clears the window: one scan gives no velocity yet.
  tracker.Update(0.0, sensor, scan_at(0.0));
  for (const TrackedObject& o : tracker.objects()) EXPECT_FALSE(o.moving);
}

TEST(MovingObjectTrackerTest, TwoPeoplePassingCloseKeepTheirTracksAndVelocities) {
  // Two people walking opposite ways pass with their shoulders almost touching: for a moment their points form one
  // cluster. Each keeps its track (the same id) and its velocity through it.
  std::mt19937 rng(11);
  MovingObjectTracker tracker{MovingObjectOptions{}};
  tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
  const Eigen::Vector2d sensor(3.0, 2.0);
  const auto a_at = [](double t) { return Eigen::Vector2d(2.5 + 0.8 * t, 5.0); };
  const auto b_at = [](double t) { return Eigen::Vector2d(7.5 - 0.8 * t, 5.55); };
  const auto nearest = [&](const Eigen::Vector2d& p) {
    const TrackedObject* best = nullptr;
    for (const TrackedObject& o : tracker.objects()) {
      if (!best || (o.position - p).norm() < (best->position - p).norm()) best = &o;
    }
    return best;
  };
  int a_id = 0;
  int b_id = 0;
  bool merged = false;
  for (int k = 0; k <= 60; ++k) {
    const double t = 0.1 * k;
    const auto ranges = Scan(sensor, {{a_at(t), 0.25}, {b_at(t), 0.25}}, 10.0, rng);
    tracker.Update(t, sensor, ToWorld(sensor, ranges));
    std::size_t seen_moving = 0;
    for (const TrackedObject& o : tracker.objects()) seen_moving += o.moving && o.seen ? 1 : 0;
    merged = merged || seen_moving < 2;
    if (k == 15) {  // t = 1.5 s: well apart, tracked
      ASSERT_NE(nearest(a_at(t)), nullptr);
      a_id = nearest(a_at(t))->id;
      b_id = nearest(b_at(t))->id;
      ASSERT_NE(a_id, b_id);
    }
  }
  EXPECT_TRUE(merged) << "the two never shared a cluster: the test does not test the crossing";
  const double t = 6.0;
  const TrackedObject* a = nearest(a_at(t));
  const TrackedObject* b = nearest(b_at(t));
  ASSERT_TRUE(a != nullptr && b != nullptr && a != b);
  EXPECT_EQ(a->id, a_id);
  EXPECT_EQ(b->id, b_id);
  EXPECT_LT((a->velocity - Eigen::Vector2d(0.8, 0.0)).norm(), 0.15);
  EXPECT_LT((b->velocity - Eigen::Vector2d(-0.8, 0.0)).norm(), 0.15);
}

TEST(MovingObjectTrackerTest, TwoPeopleWalkingSideBySideAreStillTwoPeopleWalking) {
  // Two people walking the same way 1 m apart close up to walk shoulder to shoulder for 2.5 s: their points are one
  // cluster all that while, too wide for one person, so it gives no velocity. Each keeps its track, walking, rather
  // than both being dropped after coast_s and the pair taken for something standing (which the robot would not step
  // out of the way of).
  std::mt19937 rng(3);
  MovingObjectTracker tracker{MovingObjectOptions{}};
  tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
  const Eigen::Vector2d sensor(8.5, 5.3);  // ahead of them: neither hides the other
  const auto a_at = [](double t) { return Eigen::Vector2d(1.5 + 0.8 * t, 5.0); };
  const auto b_at = [](double t) {
    return Eigen::Vector2d(1.5 + 0.8 * t, t < 1.5 ? 6.0 : std::max(5.55, 6.0 - 0.9 * (t - 1.5)));
  };
  bool merged = false;
  for (int k = 0; k <= 45; ++k) {
    const double t = 0.1 * k;
    const auto ranges = Scan(sensor, {{a_at(t), 0.25}, {b_at(t), 0.25}}, 10.0, rng);
    tracker.Update(t, sensor, ToWorld(sensor, ranges));
    if (t < 1.5) continue;
    for (const auto& person : {a_at(t), b_at(t)}) {
      // The laser sees their near sides, 0.16 m ahead of their centres; B's velocity is right again a few scans
      // after B stopped stepping toward A.
      const Eigen::Vector2d seen_at = person + Eigen::Vector2d(0.16, 0.0);
      const auto& objects = tracker.objects();
      const auto walking = std::find_if(objects.begin(), objects.end(), [&](const TrackedObject& o) {
        return o.moving && (o.position - seen_at).norm() < 0.15 &&
               (t < 2.5 || (o.velocity - Eigen::Vector2d(0.8, 0.0)).norm() < 0.15);
      });
      EXPECT_NE(walking, objects.end()) << "nobody walking at " << person.transpose() << ", t = " << t;
    }
    for (const TrackedObject& o : tracker.objects()) {
      EXPECT_FALSE(!o.moving && (o.position - a_at(t)).norm() < 0.8) << "something standing at t = " << t;
      merged = merged || (o.moving && !o.seen);
    }
  }
  EXPECT_TRUE(merged) << "the two were never one cluster: the test does not test walking together";
}

struct TurnSeen {
  double after_s = std::numeric_limits<double>::infinity();  // infinity: never
  bool lost = false;  // the walker's track stopped counting as moving at some scan after the first second
};

// How long after a person walking at 0.8 m/s along +x turns round on the spot the nearest track's velocity points
// back (x below -0.4 m/s).
TurnSeen SeeATurn(const MovingObjectOptions& options) {
  std::mt19937 rng(5);
  MovingObjectTracker tracker{options};
  tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
  const Eigen::Vector2d sensor(2.0, 2.0);
  const double turn_s = 3.0;
  TurnSeen seen;
  const auto at = [&](double t) { return Eigen::Vector2d(3.0 + 0.8 * (t < turn_s ? t : 2.0 * turn_s - t), 5.0); };
  for (int k = 0; k <= 60; ++k) {
    const double t = 0.1 * k;
    const auto ranges = Scan(sensor, {{at(t), 0.25}}, 10.0, rng);
    tracker.Update(t, sensor, ToWorld(sensor, ranges));
    const TrackedObject* person = nullptr;
    for (const TrackedObject& o : tracker.objects()) {
      if (!person || (o.position - at(t)).norm() < (person->position - at(t)).norm()) person = &o;
    }
    if (t < 1.0) continue;
    seen.lost = seen.lost || person == nullptr || !person->moving;
    if (t > turn_s && person != nullptr && person->velocity.x() < -0.4) {
      seen.after_s = t - turn_s;
      return seen;
    }
  }
  return seen;
}

TEST(MovingObjectTrackerTest, APersonTurningRoundIsSeenWalkingBackWithinAFewScans) {
  // At a walk's end people turn round on the spot. The window's halves straddle the turn for a second; the track's
  // own last positions show it within a few scans.
  const TurnSeen seen = SeeATurn(MovingObjectOptions{});
  EXPECT_LE(seen.after_s, 0.35);
  EXPECT_FALSE(seen.lost) << "the walker stopped counting as moving";
  // The window's halves alone take longer, and the walker seems to stand still in between.
  MovingObjectOptions halves_only;
  halves_only.maneuver_mps = std::numeric_limits<double>::infinity();
  const TurnSeen slow = SeeATurn(halves_only);
  EXPECT_GT(slow.after_s, seen.after_s + 0.2) << "the turn test does not test the turn";
  EXPECT_TRUE(slow.lost);
}

TEST(MovingObjectTrackerTest, WhereSomeonePacingTurnedRoundIsTheEndOfTheirWalk) {
  // A person paces between x = 2 and x = 7 at 0.8 m/s (6.25 s each way), starting at x = 2. Until they have turned
  // at an end, walking toward it tells nothing; once they have, walking toward it again reports it.
  std::mt19937 rng(3);
  MovingObjectTracker tracker{MovingObjectOptions{}};
  tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
  const Eigen::Vector2d sensor(4.5, 3.0);
  const double leg_s = 6.25;
  const auto at = [&](double t) {
    const double phase = std::fmod(t, 2.0 * leg_s);
    return Eigen::Vector2d(2.0 + 0.8 * (phase < leg_s ? phase : 2.0 * leg_s - phase), 5.0);
  };
  int early_ends = 0;  // reported in the first walk out and back (away from the far turn)
  int walks_seen = 0;  // scans of the third and fourth legs, mid-walk, with the person tracked as moving
  int right_ends = 0;  // of them, with the end ahead within 0.3 m of where they turn
  for (int k = 0; k <= 250; ++k) {
    const double t = 0.1 * k;
    const auto ranges = Scan(sensor, {{at(t), 0.25}}, 10.0, rng);
    tracker.Update(t, sensor, ToWorld(sensor, ranges));
    const TrackedObject* person = nullptr;
    for (const TrackedObject& o : tracker.objects()) {
      if (!person || (o.position - at(t)).norm() < (person->position - at(t)).norm()) person = &o;
    }
    ASSERT_NE(person, nullptr);
    if (t > 1.0 && t < 2.0 * leg_s - 0.5 && std::abs(t - leg_s) > 1.0 && person->turn_at) ++early_ends;
    const double phase = std::fmod(t, leg_s);
    if (t > 2.0 * leg_s && phase > 1.0 && phase < leg_s - 1.0 && person->moving) {
      ++walks_seen;
      const Eigen::Vector2d end(t < 3.0 * leg_s ? 7.0 : 2.0, 5.0);
      if (person->turn_at && (*person->turn_at - end).norm() < 0.3) ++right_ends;
    }
  }
  EXPECT_EQ(early_ends, 0) << "an end reported before anyone turned there";
  EXPECT_GT(walks_seen, 60);
  EXPECT_EQ(right_ends, walks_seen);
}

// A camera-like scan: the beams of Scan within half_angle of the direction `yaw` the camera looks in, none beyond; a
// disc cut by the view's edge is left out, as nav/ground/depth_scan.h leaves out what touches the image's sides.
std::vector<Eigen::Vector2d> NarrowScan(const Eigen::Vector2d& sensor, const std::vector<Disc>& discs,
                                        double half_angle, std::mt19937& rng, double yaw = 0.0) {
  const auto off_axis = [yaw](double a) { return std::abs(std::remainder(a - yaw, 2.0 * std::numbers::pi)); };
  std::vector<Disc> whole;
  for (const Disc& d : discs) {
    const Eigen::Vector2d to = d.centre - sensor;
    if (off_axis(std::atan2(to.y(), to.x())) + std::asin(d.radius / to.norm()) <= half_angle) whole.push_back(d);
  }
  std::vector<float> ranges = Scan(sensor, whole, 10.0, rng);
  for (int i = 0; i < 360; ++i) {
    if (off_axis(-std::numbers::pi + i * std::numbers::pi / 180.0) > half_angle) ranges[i] = -1.0f;
  }
  return ToWorld(sensor, ranges);
}

const TrackedObject* Nearest(const std::vector<TrackedObject>& objects, const Eigen::Vector2d& p) {
  const TrackedObject* nearest = nullptr;
  for (const TrackedObject& o : objects) {
    if (!nearest || (o.position - p).norm() < (nearest->position - p).norm()) nearest = &o;
  }
  return nearest;
}

TEST(MovingObjectTrackerTest, SomeoneWhoWalksOutOfACamerasViewIsKeptOnTheirPrediction) {
  // A camera at (1, 5) looking along x, 40 degrees either side; a person crosses its view at x = 4 walking +y and
  // leaves it at about y = 7. They are still there: predicted, not seen, for unseen_coast_s; with a view all round
  // (nothing said), after coast_s they are gone.
  const Eigen::Vector2d sensor(1.0, 5.0);
  const double half = 40.0 * std::numbers::pi / 180.0;
  const SensorView view{{sensor.x(), sensor.y(), 0.0}, half, 6.0};
  const auto at = [](double t) { return Eigen::Vector2d(4.0, 3.5 + 0.8 * t); };
  for (const bool narrow : {true, false}) {
    SCOPED_TRACE(narrow ? "camera view" : "no view given");
    std::mt19937 rng(5);
    MovingObjectOptions options;
    options.coast_s = 0.8;
    options.unseen_coast_s = 4.0;
    MovingObjectTracker tracker{options};
    tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
    double left_s = -1.0;  // when the person left the view (their track stopped being seen)
    double last_s = -1.0;  // the last scan the track was reported in
    for (int k = 0; k <= 100; ++k) {
      const double t = 0.1 * k;
      tracker.Update(t, sensor, NarrowScan(sensor, {{at(t), 0.25}}, half, rng),
                     narrow ? std::optional<SensorView>(view) : std::nullopt);
      const TrackedObject* person = Nearest(tracker.objects(), at(t));
      if (person == nullptr || (person->position - at(t)).norm() > 0.4) continue;
      if (!person->seen && left_s < 0.0) left_s = t;
      if (person->seen) left_s = -1.0;
      last_s = t;
      if (!person->seen) {
        EXPECT_TRUE(person->moving);
      }
    }
    ASSERT_GT(left_s, 4.0);
    EXPECT_LT(left_s, 5.5);
    EXPECT_NEAR(last_s - left_s, (narrow ? 4.0 : 0.8) - 0.1, 0.25);
  }
}

TEST(MovingObjectTrackerTest, SomeoneNotSeenWhereTheCameraLooksIsGone) {
  // The person stops being in the scans (sat down behind something low, say) in the middle of the view: a view
  // that covers where they should be says they are gone, after coast_s as without one.
  const Eigen::Vector2d sensor(1.0, 5.0);
  const double half = 40.0 * std::numbers::pi / 180.0;
  const SensorView view{{sensor.x(), sensor.y(), 0.0}, half, 6.0};
  std::mt19937 rng(6);
  MovingObjectTracker tracker{MovingObjectOptions{}};
  tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
  const auto at = [](double t) { return Eigen::Vector2d(4.0, 4.0 + 0.8 * t); };
  double last_s = -1.0;
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.1 * k;
    const std::vector<Disc> people = t < 1.5 ? std::vector<Disc>{{at(t), 0.25}} : std::vector<Disc>{};
    tracker.Update(t, sensor, NarrowScan(sensor, people, half, rng), view);
    if (!tracker.objects().empty()) last_s = t;
  }
  EXPECT_NEAR(last_s - 1.5, MovingObjectOptions{}.coast_s, 0.15);
}

TEST(MovingObjectTrackerTest, SomeonePacingOutOfViewTurnsAtTheEndOfTheirWalkAndIsTheSameTrackBack) {
  // A person paces between y = 3.5 and y = 8 at x = 4 (5.6 s each way). The camera at (1, 5) first sees all round,
  // long enough to see both ends; then only 40 degrees either side of x, so the end at y = 8 is out of view. Each
  // time the person walks out of view there, they are predicted turning round at the end and coming back, and are
  // taken up again as the same track when they come back into view.
  const Eigen::Vector2d sensor(1.0, 5.0);
  const double half = 40.0 * std::numbers::pi / 180.0;
  const SensorView view{{sensor.x(), sensor.y(), 0.0}, half, 6.0};
  const double leg_s = 4.5 / 0.8;
  const auto at = [&](double t) {
    const double phase = std::fmod(t, 2.0 * leg_s);
    return Eigen::Vector2d(4.0, 3.5 + 0.8 * (phase < leg_s ? phase : 2.0 * leg_s - phase));
  };
  std::mt19937 rng(8);
  MovingObjectTracker tracker{MovingObjectOptions{}};
  tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
  int unseen = 0;  // scans with the person out of view and reported on their prediction
  int turned = 0;  // of them, walking back (-y) after the end
  std::optional<int> id;
  for (int k = 0; k <= 400; ++k) {
    const double t = 0.1 * k;
    const bool narrow = t > 2.0 * leg_s + 1.0;
    const auto points = narrow ? NarrowScan(sensor, {{at(t), 0.25}}, half, rng)
                               : NarrowScan(sensor, {{at(t), 0.25}}, std::numbers::pi, rng);
    tracker.Update(t, sensor, points, narrow ? std::optional<SensorView>(view) : std::nullopt);
    if (!narrow) continue;
    const TrackedObject* person = Nearest(tracker.objects(), at(t));
    ASSERT_NE(person, nullptr) << "t " << t;
    EXPECT_LT((person->position - at(t)).norm(), 0.5) << "t " << t;
    if (!id) id = person->id;
    EXPECT_EQ(person->id, *id) << "t " << t << ": the person was lost and taken for someone new";
    if (!person->seen) {
      ++unseen;
      if (std::fmod(t, 2.0 * leg_s) > leg_s + 0.3) turned += person->velocity.y() < -0.5 ? 1 : 0;
    }
  }
  EXPECT_GT(unseen, 25);  // three walks out of view
  EXPECT_GT(turned, 10);
}

TEST(MovingObjectTrackerTest, SomeoneBackInViewBehindTheirPredictionIsStillTheSameTrack) {
  // A camera at (1, 5) sees a person walking +y at x = 4 at 0.8 m/s, then looks away (down -y) for 4 s, in which
  // the person slows to 0.65 m/s, then looks at them again (40 degrees up): they are 0.6 m behind their prediction.
  // The prediction's gate has widened with the time unseen, so they are taken up as the same track; with a gate
  // that does not widen, the prediction matches nobody and is dropped, and they become a new track.
  const Eigen::Vector2d sensor(1.0, 5.0);
  const double half = 40.0 * std::numbers::pi / 180.0;
  const auto at = [](double t) { return Eigen::Vector2d(4.0, t < 2.0 ? 3.5 + 0.8 * t : 5.1 + 0.55 * (t - 2.0)); };
  const auto looking = [](double t) { return t < 2.0 ? 0.0 : t < 6.0 ? -std::numbers::pi / 2.0 : 0.7; };
  for (const double growth : {MovingObjectOptions{}.gate_growth_mps, 0.0}) {
    SCOPED_TRACE(growth > 0.0 ? "gate widening" : "fixed gate");
    std::mt19937 rng(9);
    MovingObjectOptions options;
    options.gate_growth_mps = growth;
    MovingObjectTracker tracker{options};
    tracker.SetMap(std::make_shared<const OccupancyGrid>(Room(10.0)));
    int before = -1;  // the person's track when the camera looked away
    int after = -1;   // and when it is seen again
    for (int k = 0; k <= 70; ++k) {
      const double t = 0.1 * k;
      const double yaw = looking(t);
      tracker.Update(t, sensor, NarrowScan(sensor, {{at(t), 0.25}}, half, rng, yaw),
                     SensorView{{sensor.x(), sensor.y(), yaw}, half, 6.0});
      const TrackedObject* person = Nearest(tracker.objects(), at(t));
      if (person == nullptr || !person->seen || (person->position - at(t)).norm() > 0.4) continue;
      (t < 2.0 ? before : after) = person->id;
    }
    ASSERT_GE(before, 0);
    ASSERT_GE(after, 0);
    if (growth > 0.0) {
      EXPECT_EQ(after, before);
    } else {
      EXPECT_NE(after, before);
    }
  }
}

TEST(MovingObjectTrackerTest, BadOptionsAreRefused) {
  MovingObjectOptions o;
  o.window_scans = 1;
  EXPECT_THROW(MovingObjectTracker{o}, std::invalid_argument);
  o = {};
  o.cluster_distance_m = 0.0;
  EXPECT_THROW(MovingObjectTracker{o}, std::invalid_argument);
  o = {};
  o.unseen_coast_s = 0.5 * o.coast_s;
  EXPECT_THROW(MovingObjectTracker{o}, std::invalid_argument);
  o = {};
  o.merged_hold_s = 0.5 * o.coast_s;
  EXPECT_THROW(MovingObjectTracker{o}, std::invalid_argument);
  o = {};
  o.gate_growth_mps = -0.1;
  EXPECT_THROW(MovingObjectTracker{o}, std::invalid_argument);
  o = {};
  o.max_gate_m = 0.5 * o.gate_m;
  EXPECT_THROW(MovingObjectTracker{o}, std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav

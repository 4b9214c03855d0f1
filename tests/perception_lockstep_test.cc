// People found through the daemon's graph in simulated time (testing/lockstep_robot.h): the image detector on the
// simulator's colour image, the laser's tracker, and the depth image joined in the perception node as on a robot with
// an RGB-D camera (the simulator's own people detector, which reads the truth, is not used).
#include <gtest/gtest.h>

#include <unistd.h>

#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "drivers/sim/world.h"
#include "nav/map/map_io.h"
#include "server/runtime/topics.h"
#include "testing/lockstep_robot.h"

namespace corridor {
namespace {

using testing::LockstepRobot;

// A person the image's detector does not find (the simulator draws people as plain prisms) is found in the depth
// image where the laser's tracker has an object: a person, located where the simulator has them.
TEST(PerceptionLockstep, APersonTheImageDetectorMissesIsFoundInTheDepthImageWhereTheTrackerSeesThem) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("corridor_people_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  nav::SaveMap(drivers::sim::RoomMap(6.0, 3.0, 0.05), dir / "room.yaml");
  std::ofstream(dir / "corridor.yaml") << "sim:\n  world: room.yaml\n  start: {x_m: 1.0, y_m: 1.5, yaw_deg: 0}\n"
                                          "localization: {source: sim_truth}\n"
                                          "perception: {detector: hog}\n";
  {
    LockstepRobot robot(dir / "corridor.yaml", [](server::Config& c) {
      // Walking across the robot's view 2 m ahead, to and fro.
      c.sim.robot.pedestrians = {{{3.0, 0.6}, {3.0, 2.4}}};
    });
    const double people_radius_m = robot.config().sim.robot.crowd.radius_m;
    int found = 0;
    int from_depth = 0;
    double worst_m = 0.0;
    drivers::TimeNs last_ns = -1;
    // Where the person was over the last half second: a detection comes from a frame up to a detector's period old.
    std::deque<std::pair<double, Eigen::Vector2d>> walked;
    robot.StepUntil(
        [&] {
          const auto detections = robot.graph().bus().Get(server::topics::kDetections).latest();
          const auto truth = robot.graph().bus().Get(server::topics::kSimTruePose).latest();
          const auto people = robot.graph().bus().Get(server::topics::kSimPedestrians).latest();
          if (!truth || !people || people->people.empty()) return false;
          walked.emplace_back(robot.now_s(), people->people.front().position);
          while (walked.front().first < robot.now_s() - 0.5) walked.pop_front();
          if (!detections || detections->stamp_ns == last_ns) return false;
          last_ns = detections->stamp_ns;
          for (const face::Detection& d : detections->items) {
            if (d.label != "person" || !d.position) continue;
            ++found;
            if (d.source != "depth") continue;
            ++from_depth;
            // Its nearest surface, against the person's centre: within their radius and a little.
            const Eigen::Vector2d at = truth->pose.Transform(Eigen::Vector2d(d.position->x(), d.position->y()));
            double nearest_m = std::numeric_limits<double>::infinity();
            for (const auto& [t, position] : walked) nearest_m = std::min(nearest_m, (at - position).norm());
            worst_m = std::max(worst_m, nearest_m);
          }
          return from_depth >= 20;
        },
        20.0);
    EXPECT_GE(from_depth, 20) << found << " person detections, too few from the depth image";
    EXPECT_LT(worst_m, people_radius_m + 0.15);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace corridor

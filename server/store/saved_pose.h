// The robot's last pose, kept in the state directory so that a restart goes on where the robot stopped: the
// localization's estimate (with its map's name and spread) and, with the simulator, the simulated robot's true pose
// (with its world), as a real robot stays where it was. JSON, written atomically (a temporary file, then a rename),
// so a crash leaves the old pose or the new one, never half of one.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "nav/geometry/pose2.h"

namespace corridor::server {

struct SavedPose {
  std::string place;  // the map's name (localization) or the world's file (simulator) the pose is in
  nav::Pose2 pose;
  double sigma_m = 0.0;  // the estimate's spread when saved
  double sigma_rad = 0.0;
};

// The pose in `file`; nullopt when there is none. A file that cannot be read or parsed is reported by a warning in
// the log and ignored (the robot then starts from its configured pose): it never stops the daemon.
std::optional<SavedPose> LoadSavedPose(const std::filesystem::path& file);

// Writes `pose` to `file` atomically. Throws std::runtime_error naming the file when it cannot be written.
void SavePose(const std::filesystem::path& file, const SavedPose& pose);

// Whether `b` is far enough from `a` (or in another place) to be worth saving again.
bool MovedEnough(const SavedPose& a, const SavedPose& b, double metres = 0.1, double radians = 0.087);

}  // namespace corridor::server

#include "server/store/saved_pose.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace corridor::server {

std::optional<SavedPose> LoadSavedPose(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return std::nullopt;
  try {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    const nlohmann::json j = nlohmann::json::parse(text.str());
    SavedPose saved;
    saved.place = j.at("place").get<std::string>();
    saved.pose = {j.at("x").get<double>(), j.at("y").get<double>(), nav::WrapAngle(j.at("yaw").get<double>())};
    saved.sigma_m = j.value("sigma_m", 0.0);
    saved.sigma_rad = j.value("sigma_yaw", 0.0);
    if (!std::isfinite(saved.pose.x_m) || !std::isfinite(saved.pose.y_m) || !std::isfinite(saved.pose.yaw_rad) ||
        !(saved.sigma_m >= 0.0) || !(saved.sigma_rad >= 0.0)) {
      throw std::runtime_error("a number is not finite or a spread is negative");
    }
    return saved;
  } catch (const std::exception& e) {
    spdlog::warn("{}: the saved pose cannot be read ({}); starting from the configured pose", file.string(), e.what());
    return std::nullopt;
  }
}

void SavePose(const std::filesystem::path& file, const SavedPose& pose) {
  const nlohmann::json j{{"place", pose.place},      {"x", pose.pose.x_m},      {"y", pose.pose.y_m},
                         {"yaw", pose.pose.yaw_rad}, {"sigma_m", pose.sigma_m}, {"sigma_yaw", pose.sigma_rad}};
  const std::filesystem::path temporary = file.string() + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << j.dump() << "\n";
    if (!out) throw std::runtime_error(temporary.string() + ": cannot write the pose");
  }
  std::error_code ec;
  std::filesystem::rename(temporary, file, ec);
  if (ec) throw std::runtime_error(file.string() + ": cannot save the pose: " + ec.message());
}

bool MovedEnough(const SavedPose& a, const SavedPose& b, double metres, double radians) {
  return a.place != b.place || (a.pose.translation() - b.pose.translation()).norm() >= metres ||
         std::abs(nav::WrapAngle(a.pose.yaw_rad - b.pose.yaw_rad)) >= radians;
}

}  // namespace corridor::server

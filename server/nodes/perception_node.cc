#include "server/nodes/perception_node.h"

#include <cmath>

#include "face/detect/depth_people.h"
#include "face/detect/dnn_detector.h"
#include "face/detect/face_cascade.h"
#include "face/detect/hog_people.h"
#include "face/detect/locate.h"
#include "face/detect/people_detector.h"
#include "server/runtime/topics.h"

namespace corridor::server {

PerceptionNode::PerceptionNode(Executor& executor, Bus& bus, const PerceptionOptions& options,
                               const nav::PinholeCamera& camera, bool simulated)
    : PeriodicNode("perception", executor, bus, options.rate_hz),
      options_(options),
      camera_(camera),
      tracker_(options.tracker) {
  using Detector = PerceptionOptions::Detector;
  const Detector kind =
      options.detector == Detector::kAuto ? (simulated ? Detector::kSimulated : Detector::kHog) : options.detector;
  switch (kind) {
    case Detector::kSimulated: simulated_ = std::make_unique<face::SimulatedPeople>(options.sim); break;
    case Detector::kDnn: detector_ = std::make_unique<face::DnnDetector>(options.dnn); break;
    case Detector::kAuto:
    case Detector::kHog: detector_ = std::make_unique<face::HogPeopleDetector>(options.hog); break;
    case Detector::kPeople: detector_ = std::make_unique<face::PeopleDetector>(options.people); break;
  }
  // The simulator's colour image has no faces to find; the people detector looks for faces itself.
  if (options.faces && !simulated && kind != Detector::kPeople) {
    faces_ = std::make_unique<face::FaceCascadeDetector>(options.face_cascade);
  }
}

void PerceptionNode::Push(ExternalDetections detections) {
  executor().Post([this, detections = std::move(detections)]() mutable {
    Run("push", [&] { external_[detections.source] = std::move(detections); });
  });
}

std::vector<face::Detection> PerceptionNode::DetectInFrame() {
  const auto frame = rgbd_topic_.latest();
  if (!frame || (seen_frame_ && frame->sequence == last_sequence_)) return built_in_;
  seen_frame_ = true;
  last_sequence_ = frame->sequence;
  std::vector<face::Detection> found;
  const nav::PinholeCamera camera = drivers::CameraAt(*frame, camera_);  // where it looked (a pan servo turns it)
  if (simulated_) {
    const auto people = sim_pedestrians_topic_.latest();
    const auto truth = sim_true_pose_topic_.latest();
    if (people && truth) {
      std::vector<Eigen::Vector2d> where;
      for (const SimPedestrians::Person& p : people->people) where.push_back(p.position);
      found = simulated_->Detect(where, truth->pose, frame->depth_mm, camera);
    }
  } else if (!frame->color_bgr.empty()) {
    found = detector_->Detect(frame->color_bgr, frame->depth_mm);
    if (faces_) {
      std::vector<face::Detection> faces = faces_->Detect(frame->color_bgr, frame->depth_mm);
      found.insert(found.end(), faces.begin(), faces.end());
    }
  }
  // Registered depth only: the colour image must be the depth's size for the boxes to fall on the right pixels.
  const bool registered = frame->depth_mm.cols == camera_.width && frame->depth_mm.rows == camera_.height &&
                          (frame->color_bgr.empty() || frame->color_bgr.size() == frame->depth_mm.size());
  face::LocateDetections(found, registered ? frame->depth_mm : cv::Mat(), camera);
  if (!simulated_ && options_.depth_people) {
    std::vector<face::Detection> depth = face::NotAlreadyFound(DepthPeople(*frame), found);
    found.insert(found.end(), depth.begin(), depth.end());
  }
  built_in_ = std::move(found);
  return built_in_;
}

std::vector<face::Detection> PerceptionNode::DepthPeople(const drivers::RgbdFrame& frame) {
  const auto tracked = tracked_objects_topic_.latest();
  const auto pose = pose_topic_.latest();
  if (!tracked || !pose || frame.depth_mm.empty()) return {};
  // The tracker's objects (map frame) near enough to be seen, in the base frame.
  const nav::Pose2 base_T_map = pose->pose.Inverse();
  std::vector<face::DepthCandidate> candidates;
  for (const nav::TrackedObject& o : tracked->surroundings.objects) {
    if (!o.seen) continue;
    candidates.push_back({base_T_map.Transform(o.position), o.radius_m});
  }
  return face::DepthPeople(frame.depth_mm, drivers::CameraAt(frame, camera_), candidates, options_.depth);
}

void PerceptionNode::Tick() {
  const drivers::TimeNs now = clock().Now();
  std::vector<face::Detection> all = DetectInFrame();
  std::erase_if(external_, [&](const auto& e) {
    return now - e.second.received_ns > drivers::FromSeconds(std::min(e.second.ttl_s, options_.max_ttl_s));
  });
  for (const auto& [source, pushed] : external_) {
    for (face::Detection d : pushed.items) {
      if (d.position) d.bearing_rad = std::atan2(d.position->y(), d.position->x());
      all.push_back(std::move(d));
    }
  }
  const auto pose = pose_topic_.latest();
  tracker_.Assign(all, pose ? pose->pose : nav::Pose2{}, now);
  detections_topic_.Publish(Detections{now, std::move(all)});
}

}  // namespace corridor::server

// People and faces in the camera (the detection hook, face/detect), at perception.rate_hz on the perception executor,
// off the control path: the newest colour + depth frame goes through the configured detector (the simulated people
// with the simulator, whose camera shows prisms rather than people; HOG with head-and-shoulders and face cascades, or
// the user's network, on a real camera) and, with an image detector, the person-shaped objects of the tracker in the
// depth image (face/detect/depth_people.h); detections are located by the depth in their box (implausible sizes
// dropped), merged with those an external detector pushed in (Push, from POST /api/v1/detections, until their ttl),
// given track ids in the map frame, and published on perception/detections.
#pragma once

#include <map>
#include <memory>

#include "drivers/depth_camera.h"
#include "face/detect/detection.h"
#include "face/detect/simulated_people.h"
#include "face/detect/tracker.h"
#include "nav/geometry/camera_model.h"
#include "server/config/config.h"
#include "server/runtime/bus.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"

namespace corridor::server {

class PerceptionNode final : public PeriodicNode {
 public:
  // simulated: the robot is the simulator's (detector auto then means the simulated people). Throws
  // std::invalid_argument when a detector cannot be made (a cascade or a network that cannot be read).
  PerceptionNode(Executor& executor, Bus& bus, const PerceptionOptions& options, const nav::PinholeCamera& camera,
                 bool simulated);
  // Detections pushed in by an external detector, kept until their ttl; thread-safe (applied on the node's executor).
  void Push(ExternalDetections detections);

 private:
  void Tick() override;
  // The built-in detectors on the newest frame (none if it was seen already).
  std::vector<face::Detection> DetectInFrame();
  // The objects the tracker follows that `frame`'s depth image shows person-shaped.
  std::vector<face::Detection> DepthPeople(const drivers::RgbdFrame& frame);

  PerceptionOptions options_;
  nav::PinholeCamera camera_;
  std::unique_ptr<face::Detector> detector_;  // null: the simulated people
  std::unique_ptr<face::Detector> faces_;     // null: no face cascade
  std::unique_ptr<face::SimulatedPeople> simulated_;
  face::Tracker tracker_;
  std::uint64_t last_sequence_ = 0;
  bool seen_frame_ = false;
  std::vector<face::Detection> built_in_;               // from the last frame
  std::map<std::string, ExternalDetections> external_;  // by source

  // The topics it reads and writes, resolved once.
  Topic<Detections>& detections_topic_ = bus().Get(topics::kDetections);
  Topic<StampedPose>& pose_topic_ = bus().Get(topics::kPose);
  Topic<drivers::RgbdFrame>& rgbd_topic_ = bus().Get(topics::kRgbd);
  Topic<SimPedestrians>& sim_pedestrians_topic_ = bus().Get(topics::kSimPedestrians);
  Topic<StampedPose>& sim_true_pose_topic_ = bus().Get(topics::kSimTruePose);
  Topic<TrackedObjects>& tracked_objects_topic_ = bus().Get(topics::kTrackedObjects);
};

}  // namespace corridor::server

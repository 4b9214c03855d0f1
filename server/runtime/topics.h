// Every topic of the daemon, with its one name and type. The REST API, the WebSocket stream and (later) the DDS
// bridge use these names.
#pragma once

#include "server/runtime/bus.h"

namespace corridor::server::topics {

inline constexpr TopicName<drivers::WheelOdometry> kOdometry{"odom"};
inline constexpr TopicName<drivers::RgbdFrame> kRgbd{"camera/rgbd"};
// A stereo camera's frames before the multi-view filter (server/nodes/multi_view_node.h), when it is on.
inline constexpr TopicName<drivers::RgbdFrame> kRgbdRaw{"camera/rgbd_raw"};
// The camera's pan servo's readings (drivers/pan_servo.h), when one is fitted; and where the gaze sends it.
inline constexpr TopicName<drivers::PanReading> kCameraPan{"camera/pan"};
inline constexpr TopicName<double> kCameraPanTarget{"camera/pan_target"};
inline constexpr TopicName<drivers::LaserScan> kScan{"scan"};
inline constexpr TopicName<drivers::BatteryState> kBattery{"battery"};
inline constexpr TopicName<StampedPose> kPose{"pose"};  // the robot in the map frame
inline constexpr TopicName<LocalizationState> kLocalization{"localization"};
inline constexpr TopicName<LocalizationCommand> kLocalizationCommand{"localization/command"};
inline constexpr TopicName<MappingState> kMapping{"mapping"};
inline constexpr TopicName<ExploreCommand> kExploreCommand{"mapping/explore"};
inline constexpr TopicName<ExploreState> kExploreState{"mapping/exploring", true};
inline constexpr TopicName<StampedPose> kSimTruePose{"sim/true_pose"};          // ground truth, simulator only
inline constexpr TopicName<SimPedestrians> kSimPedestrians{"sim/pedestrians"};  // simulator only
inline constexpr TopicName<TeleopCommand> kTeleop{"teleop"};
inline constexpr TopicName<BaseCommand> kCmdVel{"cmd_vel"};
inline constexpr TopicName<Bumped> kBumped{"safety/bumped"};
inline constexpr TopicName<Fault> kFaults{"safety/faults"};                  // a node's callback threw
inline constexpr TopicName<DeviceLinkChange> kDeviceLinks{"devices/links"};  // native drivers' links
inline constexpr TopicName<DevicesHealth> kDevices{"devices"};
inline constexpr TopicName<FaceState> kFaceExpression{"face/expression"};
inline constexpr TopicName<FaceCommand> kFaceCommand{"face/command"};
inline constexpr TopicName<Detections> kDetections{"perception/detections"};
inline constexpr TopicName<MissionCommand> kMissionCommand{"mission/command"};
inline constexpr TopicName<MissionState> kMission{"mission"};
// The mission's state each time its status or leg changes: every one, in order (the database records them).
inline constexpr TopicName<MissionState> kMissionChanges{"mission/changes", false, Delivery::kEvery};
inline constexpr TopicName<FloorArrival> kFloorArrival{"mission/floor_arrival", false, Delivery::kEvery};
inline constexpr TopicName<LocalStepState> kLocalStep{"mission/step"};  // each local step, on a depth frame
inline constexpr TopicName<GroundLanes> kGroundLanes{"ground/lanes"};
inline constexpr TopicName<TrackedObjects> kTrackedObjects{"tracking/objects"};
inline constexpr TopicName<FleetOrder> kFleetOrder{"fleet/order"};  // a fleet manager's order (VDA 5050)
inline constexpr TopicName<DoorRequests> kDoorRequests{"doors/requests"};
inline constexpr TopicName<DoorStates> kDoorStates{"doors/state"};
inline constexpr TopicName<LiftRequests> kLiftRequests{"lifts/requests"};
inline constexpr TopicName<LiftStates> kLiftStates{"lifts/state"};
inline constexpr TopicName<ControlLatency> kControlLatency{"control/latency"};
// What holds rather than what happens: latched (a node subscribing gets the latest at once).
inline constexpr TopicName<MapInUse> kMapInUse{"map/in_use", true};
inline constexpr TopicName<ExploringMap> kExploringMap{"map/exploring", true};
inline constexpr TopicName<TrafficLayer> kTrafficLayer{"planner/traffic", true};
inline constexpr TopicName<ObstacleLayer> kObstacleLayer{"planner/obstacles", true};

}  // namespace corridor::server::topics

// Types of the corridord API (server/api/openapi.json is the contract) and small fetch helpers.

export interface Pose { x: number; y: number; yaw: number; }
export interface Twist { linear_mps: number; angular_rps: number; }
export interface NodeStatus {
  name: string; executor: string; health: 'ok' | 'degraded' | 'error' | 'inactive'; message: string;
  rate_hz: number; mean_loop_ms: number; worst_loop_ms: number; loops: number;
}
export interface State {
  stamp_s: number;
  pose: Pose | null;
  velocity: Twist;
  bumper_pressed: boolean;
  mode: 'starting' | 'idle' | 'teleop' | 'mission' | 'docking' | 'stopped';
  stop_reason: string;
  command: Twist;
  sim_true_pose: Pose | null;
  face: 'neutral' | 'happy' | 'focused' | 'surprised' | 'worried' | 'sleepy' | 'confused' | 'sad';
  mission: Mission | null;
  map: { name: string; revision: number; traffic: boolean };
  nodes: NodeStatus[];
  sim_pedestrians: SimPerson[];
  sim_obstacles: SimObstacle[];
  tracked_objects: TrackedObject[];
  control_latency: ControlLatency | null;
  battery: Battery | null;
  docked: boolean;
  fleet: FleetOrder | null;
  floor: string | null;
  devices: Device[];
  localization: { health: 'ok' | 'uncertain' | 'lost'; agreement: number; sigma_m: number } | null;
  process: { cpu_percent: number; resident_mb: number } | null;
}
// The laser's latest scan (GET /api/v1/laser/scan), in its own frame; null ranges saw nothing.
export interface LaserScanReading {
  stamp_s: number; angle_min_rad: number; angle_increment_rad: number; range_max_m: number; ranges: (number | null)[];
  frame: 'laser'; base_T_laser: Pose; height_m: number;
}
// One of the robot's devices (GET /api/v1/devices): its driver and where it is reached, its health and data rate.
export interface Device {
  device: 'base' | 'laser' | 'camera'; driver: string; port: string; state: 'ok' | 'stale' | 'disconnected';
  rate_hz: number; age_s: number | null; link: string | null; reconnects: number; last_error: string | null;
  handoff_cpu_s: number;
}
// A fleet manager's order (VDA 5050): the last node traversed, the nodes still to traverse, base (released) then
// horizon, and their edges.
export interface FleetOrder {
  protocol: 'vda5050'; connected: boolean; order_id: string; order_update_id: number; last_node_id: string;
  nodes: { id: string; released: boolean; x: number; y: number; traversed: boolean }[];
  edges: { id: string; start: string; end: string; released: boolean }[];
}
export interface Battery { percent: number; voltage_v: number; current_a: number; charging: boolean; on_charger: boolean; }
export interface SimPerson { x: number; y: number; vx: number; vy: number; radius_m: number; }
export interface TrackedObject {
  x: number; y: number; vx: number; vy: number; radius_m: number; moving: boolean;
  seen: boolean;  // false: kept on its prediction (hidden, or walked out of the camera's view)
  walk_end?: { x: number; y: number };  // where they turned round before, walking this way
}
export interface SimObstacle { shape: 'cylinder' | 'box' | 'table'; x: number; y: number; size_m: number; yaw: number; }
export interface ControlLatency { rate_hz: number; p50_ms: number; p99_ms: number; max_ms: number; samples: number; }
export interface MapInfo {
  name: string; revision: number; resolution_m: number; width: number; height: number; origin: Pose;
  image_url: string;
}
export interface Localization {
  source: 'odometry' | 'sim_truth' | 'mcl'; sensor?: 'laser' | 'depth'; pose?: Pose;
  covariance?: number[];  // (x, y, yaw), row-major
  health: 'ok' | 'uncertain' | 'lost'; agreement?: number; particle_count: number;
  particles: [number, number, number][];
}
// PUT /api/v1/localization/pose: taken, and whether the last scan fits the map there.
export interface PoseTaken {
  pose: Pose; sigma_m: number; sigma_yaw: number; agrees: boolean; agreement: number | null;
  agreement_before: number | null; detail: string;
}
export interface Mapping {
  active: boolean; exploring: boolean; name: string; scans: number; submaps: number; loop_closures: number;
  saved: string; error: string; map: Omit<MapInfo, 'name'> | null;
}
export interface Octomap {
  map: string; revision: number; resolution_m: number; leaves: number; occupied: number; bt_url: string;
  voxels_url: string;
}
export interface Problem { type: string; title: string; status: number; detail: string; }
// GET /api/v1/setup: whether the first admin is still to be made; the code only to the robot's own screen.
export interface SetupStatus {
  needed: boolean; code?: string; tls_fingerprint?: string;
  session: { name: string; role: 'viewer' | 'operator' | 'admin'; kind: string } | null;
}


export interface MissionWaypoint {
  x: number; y: number; yaw?: number; place?: string; action?: 'go' | 'dock' | 'undock' | 'ride_lift';
  floor?: string; lift?: string; ride_to?: string;
}
export interface Mission {
  id: string; status: 'active' | 'paused' | 'succeeded' | 'failed' | 'canceled';
  waypoints: MissionWaypoint[]; current_waypoint: number; progress: number; eta_s: number;
  remaining_on_leg_m: number; path: Pose[]; error: string; speed_limit_mps: number | null; policy?: string;
  docking: '' | 'seeking' | 'approaching' | 'final' | 'docked' | 'undocking' | 'undocked' | 'failed';
  lift?: string;
  waiting_for_door?: string;
  waiting?: string;  // what an unfinished mission waits for; "" while it goes on
}
// GET /api/v1/building: the floors (each with its map and places), the floor the robot is on, the lifts.
export interface LiftStop {
  floor: string; door: { x1: number; y1: number; x2: number; y2: number }; lobby: Pose; car: Pose;
}
export interface Lift { id: string; car_width_m: number; car_depth_m: number; stops: LiftStop[]; }
export interface Building {
  name: string; floor: string | null; floors: { name: string; map: string; places: Place[] }[]; lifts: Lift[];
}
// GET /api/v1/doors: the doors on the map in use and what their controller says.
export interface Door {
  id: string; x1: number; y1: number; x2: number; y2: number;
  state: 'idle' | 'closed' | 'opening' | 'open' | 'refused' | 'failed'; source: 'config' | 'sim' | 'drawn';
}
export interface Doors { map: string; controlled: boolean; doors: Door[]; }
export interface PathPoint { x: number; y: number; yaw: number; speed_limit_mps: number | null; }
export interface PlanResult {
  path: PathPoint[]; length_m: number; min_clearance_m: number; mean_clearance_m: number;
  expanded: number; planning_ms: number; costmap_ms: number;
}
export interface Zone {
  id: string; name: string; kind: 'keep_out' | 'speed_limit'; polygon: [number, number][]; max_speed_mps?: number;
}
export interface Place {
  id: string; name: string; x: number; y: number; yaw: number; kind: 'place' | 'dock'; staging?: Pose;
}
export interface Lane {
  offset_m: number; free_distance_m: number; dead_end: boolean; blind: boolean;
  pixel?: [number, number]; point?: [number, number, number];
}
export interface GroundLanes { frame_sequence: number; latency_ms: number; lanes: Lane[]; }
// A person or object the robot sees (perception/detections): its box in the colour image, its position in the base frame.
export interface Detection {
  class: string; score: number; track_id: number; source: string;
  box: { x: number; y: number; w: number; h: number } | null;
  position: { x: number; y: number; z: number } | null;
}
export interface Detections { stamp: number; detections: Detection[]; }
export type Goal = { x: number; y: number; yaw?: number } | { place: string };

// Every request the console makes goes through request(). Logging out ends the session only after the requests already
// on their way have been answered, and nothing is sent after it began (the page reloads): no request fails for want of
// the session it was sent with.
let leaving = false;
const inFlight = new Set<Promise<Response>>();

// fetch(), unless the page is leaving: then the request is not sent and never settles.
export function request(url: string, init?: RequestInit): Promise<Response> {
  if (leaving) return new Promise<Response>(() => undefined);
  const sent = fetch(url, init);
  inFlight.add(sent);
  sent.then(() => inFlight.delete(sent), () => inFlight.delete(sent));
  return sent;
}

// Stops sending and resolves once every request already sent is answered.
export async function leavePage(): Promise<void> {
  leaving = true;
  await Promise.allSettled([...inFlight]);
}

// Sends a JSON request; resolves the parsed body, or rejects with the problem's title and detail.
export async function send<T>(method: string, url: string, body?: unknown): Promise<T> {
  const res = await request(url, {
    method,
    cache: 'no-store',
    headers: body === undefined ? {} : { 'Content-Type': 'application/json' },
    body: body === undefined ? undefined : JSON.stringify(body),
  });
  const text = await res.text();
  const parsed = text ? JSON.parse(text) : null;
  if (!res.ok) {
    const problem = parsed as Problem | null;
    throw new Error(problem ? `${problem.title}: ${problem.detail}` : `${url}: HTTP ${res.status}`);
  }
  return parsed as T;
}

// One of the robot's events (GET /api/v1/events): what building systems are told, numbered across restarts.
export type EventType = 'person_detected' | 'person_left' | 'mission_succeeded' | 'mission_failed' | 'blocked' | 'lost' |
  'fault' | 'bump' | 'waiting' | 'battery_low';
export interface RobotEvent {
  sequence: number; time: string; type: EventType;
  data: { mission_id?: string; place?: string; detail?: string; person?: { track_id?: number } };
}

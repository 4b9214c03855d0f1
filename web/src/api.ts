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
  mode: 'starting' | 'idle' | 'teleop' | 'stopped';
  stop_reason: string;
  command: Twist;
  sim_true_pose: Pose | null;
  face: 'neutral' | 'happy' | 'focused' | 'surprised' | 'worried' | 'sleepy';
  nodes: NodeStatus[];
}
export interface MapInfo {
  name: string; resolution_m: number; width: number; height: number; origin: Pose; image_url: string;
}
export interface Problem { type: string; title: string; status: number; detail: string; }

export async function fetchJson<T>(url: string): Promise<T> {
  const res = await fetch(url, { cache: 'no-store' });
  if (!res.ok) {
    const problem = (await res.json().catch(() => null)) as Problem | null;
    throw new Error(problem ? `${problem.title}: ${problem.detail}` : `${url}: HTTP ${res.status}`);
  }
  return (await res.json()) as T;
}

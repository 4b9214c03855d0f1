// What the face looks like, apart from drawing it: each expression as a set of shape parameters, the shown face easing
// towards its target, blinks at random intervals, and the gaze. Times in milliseconds.

export type Expression =
  'neutral' | 'happy' | 'focused' | 'surprised' | 'worried' | 'sleepy' | 'confused' | 'sad';
export const EXPRESSIONS: Expression[] =
  ['neutral', 'happy', 'focused', 'surprised', 'worried', 'sleepy', 'confused', 'sad'];

// One eye and the mouth, in units of the eye's height: openness 1 is a round, open eye.
export interface Shape {
  openLeft: number;    // 0 closed .. 1.3 wide open
  openRight: number;
  lidTilt: number;     // the upper lid's slope: > 0 inner corners down (focused, cross), < 0 inner corners up (worried)
  cheek: number;       // the lower lid raised (a smile in the eyes), 0 .. 0.5
  pupil: number;       // pupil size, 0.5 .. 1.2
  smile: number;       // the mouth's curve, -1 (frown) .. 1 (smile)
  mouthOpen: number;   // 0 .. 1 (surprise, or speech)
  mouthTilt: number;   // a lopsided mouth (confused), -0.5 .. 0.5
  hue: number;         // the eyes' colour hue, degrees
}

export const SHAPES: Record<Expression, Shape> = {
  neutral: { openLeft: 1.0, openRight: 1.0, lidTilt: 0.0, cheek: 0.0, pupil: 1.0, smile: 0.15, mouthOpen: 0, mouthTilt: 0, hue: 190 },
  happy: { openLeft: 0.85, openRight: 0.85, lidTilt: -0.05, cheek: 0.4, pupil: 1.05, smile: 0.9, mouthOpen: 0.15, mouthTilt: 0, hue: 170 },
  focused: { openLeft: 0.7, openRight: 0.7, lidTilt: 0.25, cheek: 0.05, pupil: 0.85, smile: 0.0, mouthOpen: 0, mouthTilt: 0, hue: 200 },
  surprised: { openLeft: 1.3, openRight: 1.3, lidTilt: -0.1, cheek: 0.0, pupil: 0.6, smile: 0.0, mouthOpen: 0.8, mouthTilt: 0, hue: 45 },
  worried: { openLeft: 0.95, openRight: 0.95, lidTilt: -0.4, cheek: 0.0, pupil: 0.9, smile: -0.35, mouthOpen: 0.05, mouthTilt: 0, hue: 30 },
  sleepy: { openLeft: 0.22, openRight: 0.22, lidTilt: 0.0, cheek: 0.0, pupil: 0.9, smile: 0.05, mouthOpen: 0.1, mouthTilt: 0, hue: 230 },
  confused: { openLeft: 1.05, openRight: 0.6, lidTilt: 0.15, cheek: 0.0, pupil: 0.9, smile: -0.1, mouthOpen: 0, mouthTilt: 0.35, hue: 280 },
  sad: { openLeft: 0.65, openRight: 0.65, lidTilt: -0.55, cheek: 0.0, pupil: 1.1, smile: -0.85, mouthOpen: 0, mouthTilt: 0, hue: 215 },
};

const KEYS = Object.keys(SHAPES.neutral) as (keyof Shape)[];

// Random intervals between blinks, as people blink: 2 to 6 s, now and then a double blink.
export class Blinker {
  private nextAt: number;
  private startedAt = -Infinity;
  static readonly DURATION_MS = 160;

  constructor(now: number, private readonly random: () => number = Math.random) {
    this.nextAt = now + this.interval();
  }

  // How closed the eyes are for the blink now: 0 open .. 1 shut.
  closure(now: number): number {
    if (now >= this.nextAt) {
      this.startedAt = now;
      // One blink in seven is doubled: the second follows at once.
      this.nextAt = now + (this.random() < 0.15 ? 1.8 * Blinker.DURATION_MS : this.interval());
    }
    const t = (now - this.startedAt) / Blinker.DURATION_MS;
    return t >= 0 && t <= 1 ? Math.sin(Math.PI * t) : 0;
  }

  // When the next blink starts (the page sleeps until then when nothing else moves).
  next(): number {
    return this.nextAt;
  }

  private interval(): number {
    return 2000 + 4000 * this.random();
  }
}

// The shown face easing towards the target expression (about 250 ms to settle), and the gaze towards where to look.
export class FaceState {
  expression: Expression = 'neutral';
  shape: Shape = { ...SHAPES.neutral };
  gaze = 0;          // -1 (the robot's right) .. 1 (its left)
  private gazeTarget = 0;
  private lastMs: number | null = null;

  setExpression(expression: Expression): void {
    this.expression = expression;
  }

  // gazeRad: from straight ahead, counter-clockwise (the robot's left); the eyes turn fully at maxRad.
  setGaze(gazeRad: number, maxRad = 0.7): void {
    this.gazeTarget = Math.max(-1, Math.min(1, gazeRad / maxRad));
  }

  // Moves the shown face on to `now`; returns whether it is still moving.
  step(now: number): boolean {
    const dt = this.lastMs === null ? 1000 : Math.min(200, now - this.lastMs);
    this.lastMs = now;
    const k = 1 - Math.exp(-dt / 80);  // a time constant of 80 ms
    const target = SHAPES[this.expression];
    let moving = false;
    for (const key of KEYS) {
      const d = target[key] - this.shape[key];
      this.shape[key] += d * k;
      if (Math.abs(d) > 0.002 * (key === 'hue' ? 100 : 1)) moving = true;
    }
    const dg = this.gazeTarget - this.gaze;
    this.gaze += dg * (1 - Math.exp(-dt / 60));
    if (Math.abs(dg) > 0.002) moving = true;
    return moving;
  }
}

// Teleoperation from the keyboard (arrows or WASD) and an on-screen joystick. While anything is held the current
// command is sent ten times a second; on release one stop is sent. The daemon's deadman stops the robot if the
// commands stop arriving for any other reason (a closed tab, a lost network).
import nipplejs from 'nipplejs';

import type { Twist } from './api';

const kSendPeriodMs = 100;

export interface TeleopLimits { maxLinear: number; maxAngular: number; }

export class Teleop {
  private readonly keys = new Set<string>();
  private joystick: Twist | null = null;
  private timer: number | null = null;

  constructor(
    private readonly limits: TeleopLimits,
    joystickZone: HTMLElement,
    private readonly send: (command: Twist) => void,
  ) {
    window.addEventListener('keydown', (e) => this.onKey(e, true));
    window.addEventListener('keyup', (e) => this.onKey(e, false));
    window.addEventListener('blur', () => {
      this.keys.clear();
      this.update();
    });
    const manager = nipplejs.create({ zone: joystickZone, mode: 'static', position: { left: '50%', top: '50%' },
      size: 120, color: '#58a6ff' });
    manager.on('move', (evt) => {
      const v = evt.data.vector;
      this.joystick = { linear_mps: v.y * this.limits.maxLinear, angular_rps: -v.x * this.limits.maxAngular };
      this.update();
    });
    manager.on('end', () => {
      this.joystick = null;
      this.update();
    });
  }

  private onKey(e: KeyboardEvent, down: boolean): void {
    const key = normalise(e.key);
    if (key === null) return;
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
    e.preventDefault();
    if (down) this.keys.add(key);
    else this.keys.delete(key);
    this.update();
  }

  private command(): Twist | null {
    if (this.joystick) return this.joystick;
    if (this.keys.size === 0) return null;
    const forward = (this.keys.has('up') ? 1 : 0) - (this.keys.has('down') ? 1 : 0);
    const left = (this.keys.has('left') ? 1 : 0) - (this.keys.has('right') ? 1 : 0);
    return { linear_mps: forward * this.limits.maxLinear, angular_rps: left * this.limits.maxAngular };
  }

  private update(): void {
    const command = this.command();
    if (command === null) {
      if (this.timer !== null) {
        window.clearInterval(this.timer);
        this.timer = null;
        this.send({ linear_mps: 0, angular_rps: 0 });
      }
      return;
    }
    this.send(command);
    if (this.timer === null) {
      this.timer = window.setInterval(() => {
        const c = this.command();
        if (c) this.send(c);
      }, kSendPeriodMs);
    }
  }
}

function normalise(key: string): 'up' | 'down' | 'left' | 'right' | null {
  switch (key) {
    case 'ArrowUp': case 'w': case 'W': return 'up';
    case 'ArrowDown': case 's': case 'S': return 'down';
    case 'ArrowLeft': case 'a': case 'A': return 'left';
    case 'ArrowRight': case 'd': case 'D': return 'right';
    default: return null;
  }
}

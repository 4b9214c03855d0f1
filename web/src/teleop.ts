// Teleoperation from the keyboard (arrows or WASD) and an on-screen joystick. While anything is held the current
// command is sent ten times a second; on release one stop is sent. The daemon's deadman stops the robot if the
// commands stop arriving for any other reason (a closed tab, a lost network).
//
// The keys drive whenever the focus is not in a text field: they are taken on the window before anything else sees
// them (the map, once clicked, would otherwise pan with the arrows and never let them through).
import type { Twist } from './api';
import { Joystick } from './joystick';

const kSendPeriodMs = 100;

export interface TeleopLimits { maxLinear: number; maxAngular: number; }

export class Teleop {
  private readonly keys = new Set<string>();
  private readonly stick: Joystick;
  private joystick: Twist | null = null;
  private timer: number | null = null;

  constructor(
    private readonly limits: TeleopLimits,
    joystickZone: HTMLElement,
    private readonly send: (command: Twist) => void,
  ) {
    window.addEventListener('keydown', (e) => this.onKey(e, true), { capture: true });
    window.addEventListener('keyup', (e) => this.onKey(e, false), { capture: true });
    window.addEventListener('blur', () => {
      this.keys.clear();
      this.stick.release();
      this.update();
    });
    this.stick = new Joystick(joystickZone, 60, (v) => {
      this.joystick = { linear_mps: v.y * this.limits.maxLinear, angular_rps: -v.x * this.limits.maxAngular };
      this.update();
    }, () => {
      this.joystick = null;
      this.update();
    });
  }

  private onKey(e: KeyboardEvent, down: boolean): void {
    const key = normalise(e.key);
    if (key === null || isTextField(e.target)) return;
    // A held key is let go even with a modifier pressed since; a new press with one is the browser's shortcut.
    if (down && (e.ctrlKey || e.altKey || e.metaKey)) return;
    e.preventDefault();
    e.stopPropagation();
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

// Where the keys type rather than drive: text inputs, text areas, selects (arrows pick an option) and editable text.
function isTextField(target: EventTarget | null): boolean {
  if (target instanceof HTMLTextAreaElement || target instanceof HTMLSelectElement) return true;
  if (target instanceof HTMLInputElement) {
    return !['button', 'checkbox', 'radio', 'submit', 'reset', 'color', 'file', 'image'].includes(target.type);
  }
  return target instanceof HTMLElement && target.isContentEditable;
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

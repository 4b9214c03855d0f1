// An on-screen joystick: press anywhere in its zone and drag; the knob follows within the ring, and the direction is
// the pointer's from the ring's centre. The centre is read from the layout at every pointer event, never kept: the
// joystick points where it is dragged wherever its zone has moved (a scrolled side panel, something above it growing,
// a resize, a rotation). Pointer Events serve mouse, touch and pen alike; the pointer is captured, so a drag that
// leaves the zone keeps steering until it is released.
//
// Written here rather than taken from a library: the one we used (nipplejs) measured the centre once and followed only
// the window's scrolling, so a drag down inside a scrolled panel drove the robot forward. What remains is 60 lines.

// Right and up, each in [-1, 1], of length at most 1 (1: the knob at the ring).
export interface StickVector { x: number; y: number; }

export class Joystick {
  private pointer: number | null = null;
  private readonly ring: HTMLElement;
  private readonly knob: HTMLElement;

  // `radiusPx`: how far the knob travels from the centre; the ring is drawn that size.
  constructor(
    private readonly zone: HTMLElement,
    private readonly radiusPx: number,
    private readonly onMove: (v: StickVector) => void,
    private readonly onEnd: () => void,
  ) {
    this.ring = document.createElement('div');
    this.ring.className = 'joystick-ring';
    this.ring.style.width = this.ring.style.height = `${2 * radiusPx}px`;
    this.knob = document.createElement('div');
    this.knob.className = 'joystick-knob';
    this.ring.appendChild(this.knob);
    zone.appendChild(this.ring);
    zone.addEventListener('pointerdown', (e) => {
      if (this.pointer !== null || (e.pointerType === 'mouse' && e.button !== 0)) return;
      e.preventDefault();
      zone.setPointerCapture(e.pointerId);
      this.pointer = e.pointerId;
      this.follow(e);
    });
    zone.addEventListener('pointermove', (e) => {
      if (e.pointerId === this.pointer) this.follow(e);
    });
    for (const type of ['pointerup', 'pointercancel', 'lostpointercapture'] as const) {
      zone.addEventListener(type, (e) => {
        if (e.pointerId === this.pointer) this.release();
      });
    }
  }

  get active(): boolean { return this.pointer !== null; }

  // Lets go as if the pointer had been released (the window lost focus).
  release(): void {
    if (this.pointer === null) return;
    if (this.zone.hasPointerCapture(this.pointer)) this.zone.releasePointerCapture(this.pointer);
    this.pointer = null;
    this.knob.style.transform = '';
    this.onEnd();
  }

  private follow(e: PointerEvent): void {
    const box = this.ring.getBoundingClientRect();
    const dx = e.clientX - (box.left + box.width / 2);
    const dy = e.clientY - (box.top + box.height / 2);
    const scale = Math.min(1, this.radiusPx / Math.max(Math.hypot(dx, dy), 1e-9));
    this.knob.style.transform = `translate(${dx * scale}px, ${dy * scale}px)`;
    this.onMove({ x: (dx * scale) / this.radiusPx, y: (-dy * scale) / this.radiusPx });
  }
}

// Draws the face on a canvas: two eyes (lids, pupils that follow the gaze) and a mouth, black background, sized to
// fill any screen from 800 x 480 up.
import type { Shape } from './model';

export interface Frame {
  shape: Shape;
  blink: number;     // 0 open .. 1 shut
  gaze: number;      // -1 (the robot's right) .. 1 (its left)
  speaking: number;  // 0 .. 1: the mouth's opening from speech
  connected: boolean;
}

export function drawFace(ctx: CanvasRenderingContext2D, width: number, height: number, f: Frame): void {
  ctx.fillStyle = '#000';
  ctx.fillRect(0, 0, width, height);
  const eyeW = Math.min(width * 0.2, height * 0.32);
  const eyeH = eyeW * 1.15;
  const cy = height * 0.42;
  const dx = Math.min(width * 0.22, eyeW * 1.45);
  const colour = f.connected ? `hsl(${f.shape.hue}, 85%, 62%)` : 'hsl(0, 0%, 35%)';
  // The robot's left is the viewer's right: a gaze to its left moves the pupils right.
  drawEye(ctx, width / 2 - dx, cy, eyeW, eyeH, f.shape.openRight * (1 - f.blink), f.shape, -1, f.gaze, colour);
  drawEye(ctx, width / 2 + dx, cy, eyeW, eyeH, f.shape.openLeft * (1 - f.blink), f.shape, 1, f.gaze, colour);
  drawMouth(ctx, width / 2, height * 0.78, eyeW * 0.9, f, colour);
}

// side: -1 the eye on the viewer's left, 1 on the right (its inner corner is towards the middle).
function drawEye(ctx: CanvasRenderingContext2D, x: number, y: number, w: number, h: number, open: number,
  s: Shape, side: number, gaze: number, colour: string): void {
  const shown = Math.max(0.04, Math.min(1.3, open));
  const eh = h * shown;
  ctx.save();
  ctx.beginPath();
  roundedRect(ctx, x - w / 2, y - eh / 2, w, eh, Math.min(w, eh) * 0.45);
  ctx.clip();
  ctx.fillStyle = colour;
  ctx.fillRect(x - w / 2, y - eh / 2, w, eh);
  // The pupil, following the gaze.
  const pr = w * 0.2 * s.pupil;
  ctx.fillStyle = 'rgba(0, 0, 0, 0.55)';
  ctx.beginPath();
  ctx.arc(x + gaze * w * 0.22, y + eh * 0.05, pr, 0, Math.PI * 2);
  ctx.fill();
  ctx.fillStyle = 'rgba(255, 255, 255, 0.85)';
  ctx.beginPath();
  ctx.arc(x + gaze * w * 0.22 - pr * 0.35, y - pr * 0.35, pr * 0.28, 0, Math.PI * 2);
  ctx.fill();
  // The upper lid's slope: inner corner down (lidTilt > 0) or up (< 0).
  ctx.fillStyle = '#000';
  const inner = x - side * w / 2;
  const outer = x + side * w / 2;
  const top = y - eh / 2;
  const drop = s.lidTilt * h * 0.45;
  ctx.beginPath();
  ctx.moveTo(inner, top - h);
  ctx.lineTo(outer, top - h);
  ctx.lineTo(outer, top + Math.max(0, -drop));
  ctx.lineTo(inner, top + Math.max(0, drop));
  ctx.closePath();
  ctx.fill();
  // The lower lid raised: a smile in the eyes.
  if (s.cheek > 0.01) {
    ctx.beginPath();
    ctx.ellipse(x, y + eh / 2 + h * 0.35 - s.cheek * h * 0.6, w * 0.75, h * 0.45, 0, 0, Math.PI * 2);
    ctx.fill();
  }
  ctx.restore();
}

function drawMouth(ctx: CanvasRenderingContext2D, x: number, y: number, half: number, f: Frame, colour: string): void {
  const s = f.shape;
  const open = Math.max(s.mouthOpen, f.speaking);
  const tilt = s.mouthTilt * half * 0.4;
  const curve = s.smile * half * 0.45;
  ctx.strokeStyle = colour;
  ctx.fillStyle = colour;
  ctx.lineWidth = Math.max(3, half * 0.09);
  ctx.lineCap = 'round';
  if (open > 0.05) {
    // An open mouth: the curve's two lips apart.
    const gap = open * half * 0.45;
    ctx.beginPath();
    ctx.moveTo(x - half * 0.6, y + tilt);
    ctx.quadraticCurveTo(x, y - gap / 2 + curve * 0.5, x + half * 0.6, y - tilt);
    ctx.quadraticCurveTo(x, y + gap + curve, x - half * 0.6, y + tilt);
    ctx.closePath();
    ctx.globalAlpha = 0.85;
    ctx.fill();
    ctx.globalAlpha = 1;
    return;
  }
  ctx.beginPath();
  ctx.moveTo(x - half, y + tilt);
  ctx.quadraticCurveTo(x, y + curve * 2, x + half, y - tilt);
  ctx.stroke();
}

function roundedRect(ctx: CanvasRenderingContext2D, x: number, y: number, w: number, h: number, r: number): void {
  ctx.moveTo(x + r, y);
  ctx.arcTo(x + w, y, x + w, y + h, r);
  ctx.arcTo(x + w, y + h, x, y + h, r);
  ctx.arcTo(x, y + h, x, y, r);
  ctx.arcTo(x, y, x + w, y, r);
  ctx.closePath();
}

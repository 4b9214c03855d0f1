// The face kiosk page at /face, for the robot's front screen: the expression, gaze and speech the daemon's face node
// publishes on face/expression, drawn full screen. It reconnects by itself and shows when it is not connected. The
// page redraws only while something moves (an expression easing, a blink, the gaze, speech), so it idles at next to
// nothing. Its state is on <body> for tests: data-expression, data-gaze, data-connected, data-speaking.
// Until the robot has its first admin, the page also shows the one-time setup code (the daemon gives it only to its
// own screen, on loopback) and the fingerprint of its TLS certificate, so that whoever sets it up can check both.
import type { SetupStatus } from '../api';
import { Stream } from '../stream';
import { drawFace } from './draw';
import { Blinker, EXPRESSIONS, type Expression, FaceState } from './model';
import { Voice } from './voice';

interface FaceMessage {
  expression: string;
  gaze: number;
  gaze_at_person: boolean;
  said_sequence: number;
  said: string;
  said_kind: string;
}

const canvas = document.getElementById('face') as HTMLCanvasElement;
const status = document.getElementById('status') as HTMLElement;
const ctx = canvas.getContext('2d') as CanvasRenderingContext2D;
const face = new FaceState();
const blinker = new Blinker(performance.now());
const voice = new Voice();
let connected = false;
let lastSaid: number | null = null;
let animation: number | null = null;  // a frame requested
let sleep: number | null = null;      // a timer until the next blink
let width = 0;
let height = 0;

function resize(): void {
  const ratio = window.devicePixelRatio || 1;
  width = window.innerWidth;
  height = window.innerHeight;
  canvas.width = Math.round(width * ratio);
  canvas.height = Math.round(height * ratio);
  ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
  wake();
}

function frame(now: number): void {
  animation = null;
  const moving = face.step(now);
  const blink = blinker.closure(now);
  const speaking = voice.level();
  drawFace(ctx, width, height, { shape: face.shape, blink, gaze: face.gaze, speaking, connected });
  document.body.dataset.gaze = face.gaze.toFixed(2);
  document.body.dataset.speaking = String(voice.speaking());
  document.body.dataset.still = String(!moving);  // eased into the expression and the gaze asked for
  if (moving || blink > 0 || voice.speaking()) {
    animation = requestAnimationFrame(frame);
  } else {
    // Nothing moves: sleep until the next blink.
    sleep = window.setTimeout(() => {
      sleep = null;
      wake();
    }, Math.max(16, blinker.next() - now));
  }
}

// Draws again at the next frame (something changed).
function wake(): void {
  if (animation !== null) return;
  if (sleep !== null) window.clearTimeout(sleep);
  sleep = null;
  animation = requestAnimationFrame(frame);
}

let lastMessage = '';

function onFace(data: FaceMessage): void {
  // The stream repeats the newest message 20 times a second: only a change wakes the drawing.
  const key = `${data.expression} ${data.gaze.toFixed(3)} ${data.said_sequence}`;
  if (key === lastMessage) return;
  lastMessage = key;
  const expression = (EXPRESSIONS as string[]).includes(data.expression) ? (data.expression as Expression) : 'neutral';
  face.setExpression(expression);
  face.setGaze(data.gaze);
  document.body.dataset.expression = expression;
  document.body.dataset.still = 'false';
  // Speak what was said since the page connected (not what was said before it opened).
  if (lastSaid !== null && data.said_sequence > lastSaid && data.said) voice.say(data.said_sequence, data.said);
  lastSaid = data.said_sequence;
  wake();
}

function onStatus(up: boolean): void {
  connected = up;
  document.body.dataset.connected = String(up);
  status.textContent = up ? '' : 'disconnected — reconnecting…';
  status.hidden = up;
  wake();
}

const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
new Stream(`${scheme}://${location.host}/api/v1/stream`, ['face/expression'],
  (topic, data) => { if (topic === 'face/expression') onFace(data as FaceMessage); },
  (s) => onStatus(s === 'up'));
voice.onChange = wake;

async function showSetup(): Promise<void> {
  let again = true;
  try {
    const res = await fetch('/api/v1/setup', { cache: 'no-store' });
    const setup = (await res.json()) as SetupStatus;
    const box = document.getElementById('setup') as HTMLElement;
    box.hidden = !setup.needed || !setup.code;
    (document.getElementById('setup-code') as HTMLElement).textContent = setup.code ?? '';
    (document.getElementById('setup-fingerprint') as HTMLElement).textContent =
      setup.tls_fingerprint ? `certificate SHA-256 ${setup.tls_fingerprint}` : '';
    again = setup.needed;
  } catch {
    // The daemon is restarting: ask again.
  }
  if (again) window.setTimeout(() => void showSetup(), 3000);
}
void showSetup();
window.addEventListener('resize', resize);
// A tap or key goes full screen (browsers allow it only on a gesture) and lets the page play sound.
const fullScreen = (): void => {
  voice.unlock();
  if (!document.fullscreenElement) document.documentElement.requestFullscreen?.().catch(() => undefined);
};
window.addEventListener('pointerdown', fullScreen);
window.addEventListener('keydown', fullScreen);
onStatus(false);
resize();

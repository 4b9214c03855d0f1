// MQTT for the tests: a mosquitto broker this process starts on loopback (a plain listener), and clients built on
// mosquitto_sub and mosquitto_pub.
import { execFileSync, spawn } from 'node:child_process';
import { writeFileSync } from 'node:fs';
import { createServer } from 'node:net';
import { join } from 'node:path';

import { sleep } from './daemon.mjs';

export const freePort = () => new Promise((resolve) => {
  const server = createServer().listen(0, '127.0.0.1', () => {
    const { port } = server.address();
    server.close(() => resolve(port));
  });
});

// A mosquitto broker on loopback, stopped and started again on the same port.
export class Broker {
  constructor(dir, port) {
    this.port = port;
    this.url = `mqtt://127.0.0.1:${port}`;
    this.conf = join(dir, 'mosquitto.conf');
    writeFileSync(this.conf, `listener ${port} 127.0.0.1\nallow_anonymous true\npersistence false\n`);
  }
  async start() {
    this.proc = spawn('mosquitto', ['-c', this.conf], { stdio: ['ignore', 'ignore', 'pipe'] });
    let log = '';
    this.proc.stderr.on('data', (d) => { log += d; });
    const end = Date.now() + 10000;
    while (!/running/.test(log)) {
      if (Date.now() > end) throw new Error(`mosquitto did not start: ${log}`);
      await sleep(50);
    }
  }
  async stop() {
    if (!this.proc) return;
    const exited = new Promise((r) => this.proc.on('exit', r));
    this.proc.kill('SIGTERM');
    await exited;
    this.proc = null;
  }
}

// mosquitto_sub on `topics` (QoS 1): `onMessage(topic, payload)` for each message. Returns the process (kill it).
export function subscribe(port, topics, onMessage) {
  const proc = spawn('mosquitto_sub', ['-h', '127.0.0.1', '-p', String(port), '-v', '-q', '1',
    ...topics.flatMap((t) => ['-t', t])], { stdio: ['ignore', 'pipe', 'ignore'] });
  let pending = '';
  proc.stdout.on('data', (d) => {
    pending += d;
    let newline;
    while ((newline = pending.indexOf('\n')) >= 0) {
      const line = pending.slice(0, newline);
      pending = pending.slice(newline + 1);
      const space = line.indexOf(' ');
      onMessage(line.slice(0, space), line.slice(space + 1));
    }
  });
  return proc;
}

// mosquitto_pub of one message.
export function publish(port, topic, text) {
  execFileSync('mosquitto_pub', ['-h', '127.0.0.1', '-p', String(port), '-q', '1', '-t', topic, '-m', text]);
}

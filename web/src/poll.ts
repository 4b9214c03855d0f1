// A request repeated every `periodMs` for as long as the page lives. After a failure (the daemon restarting, the
// network gone) the next try waits twice as long as the one before, up to kMaxBackoffMs, and the period is back with
// the first success: a console left open beside a stopped robot neither floods the network nor the browser's log.
const kMaxBackoffMs = 8000;

export function repeat(tick: () => Promise<void>, periodMs: number, onError: (e: Error) => void): void {
  let delay = periodMs;
  const run = async () => {
    try {
      await tick();
      delay = periodMs;
    } catch (e) {
      onError(e as Error);
      delay = Math.min(Math.max(delay, periodMs) * 2, kMaxBackoffMs);
    }
    window.setTimeout(() => void run(), delay);
  };
  void run();
}

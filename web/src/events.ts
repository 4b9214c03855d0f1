// The robot's events in the console: each new one as a notification over the map (but people coming and going, which
// only the history lists), and the history of the newest, filtered by kind. Read from GET /api/v1/events, asking
// every two seconds for those after the last one seen: none is missed however close together they come.
import { send, type EventType, type RobotEvent } from './api';
import { byId } from './dom';
import { repeat } from './poll';

const kPollMs = 2000;
const kShownMs = 8000;
const kMostToasts = 3;
const kHistory = 256;

type Severity = 'ok' | 'warn' | 'bad' | 'info';

// What each kind of event says to people, and how much it matters.
function describe(e: RobotEvent): { text: string; severity: Severity } {
  const d = e.data;
  const mission = d.place ? ` to '${d.place}'` : '';
  const texts: Record<EventType, [string, Severity]> = {
    mission_succeeded: [`Mission${mission} done`, 'ok'],
    mission_failed: [`Mission${mission} failed: ${d.detail ?? 'no reason given'}`, 'bad'],
    blocked: [d.detail === 'person' ? 'Blocked: a person is in the way' : 'Blocked: waiting for a way through', 'warn'],
    lost: ['Lost: searching the map for the robot', 'bad'],
    fault: [`Stopped: ${d.detail ?? 'a fault'}`, 'bad'],
    bump: ['Bumped into something', 'warn'],
    waiting: [`Waiting for ${d.detail ?? 'something'}`, 'warn'],
    battery_low: [`Battery low: ${d.detail ?? ''}`, 'bad'],
    person_detected: [`Person ${d.person?.track_id ?? ''} seen`, 'info'],
    person_left: [`Person ${d.person?.track_id ?? ''} left`, 'info'],
  };
  const [text, severity] = texts[e.type] ?? [e.type, 'info'];
  return { text, severity };
}

// Which kinds each filter of the history shows.
const kFilters: Record<string, EventType[] | null> = {
  all: null,
  missions: ['mission_succeeded', 'mission_failed', 'blocked', 'waiting'],
  trouble: ['fault', 'lost', 'bump', 'battery_low', 'mission_failed', 'blocked'],
  people: ['person_detected', 'person_left'],
};

export class EventsPanel {
  private history: RobotEvent[] = [];
  private last = 0;

  constructor() {
    byId<HTMLSelectElement>('events-filter').addEventListener('change', () => this.render());
  }

  // Reads the newest events (history only: what happened before the page opened is not news), then polls.
  async start(): Promise<void> {
    this.take((await send<{ events: RobotEvent[] }>('GET', '/api/v1/events')).events, false);
    repeat(async () => {
      this.take((await send<{ events: RobotEvent[] }>('GET', `/api/v1/events?after=${this.last}`)).events, true);
    }, kPollMs, () => undefined);
  }

  private take(events: RobotEvent[], notify: boolean): void {
    if (events.length === 0) return;
    for (const e of events) {
      this.last = Math.max(this.last, e.sequence);
      if (notify && e.type !== 'person_detected' && e.type !== 'person_left') this.toast(e);
    }
    this.history = [...events.slice().reverse(), ...this.history].slice(0, kHistory);
    this.render();
  }

  private render(): void {
    const kinds = kFilters[byId<HTMLSelectElement>('events-filter').value] ?? null;
    const rows = this.history.filter((e) => kinds === null || kinds.includes(e.type)).map((e) => {
      const { text, severity } = describe(e);
      const li = document.createElement('li');
      li.className = `event ${severity}`;
      li.dataset.type = e.type;
      const time = document.createElement('time');
      time.dateTime = e.time;
      time.textContent = new Date(e.time).toLocaleTimeString();
      li.append(time, ` ${text}`);
      return li;
    });
    const list = byId('events-list');
    list.replaceChildren(...rows);
    byId('events-empty').hidden = rows.length > 0;
  }

  // A notification over the map: the newest on top, a few at most, each gone after a while or when tapped.
  private toast(e: RobotEvent): void {
    const { text, severity } = describe(e);
    const toasts = byId('toasts');
    const toast = document.createElement('button');
    toast.className = `toast ${severity}`;
    toast.dataset.type = e.type;
    toast.textContent = text;
    toast.title = 'Dismiss';
    toast.addEventListener('click', () => toast.remove());
    toasts.prepend(toast);
    while (toasts.children.length > kMostToasts) toasts.lastElementChild?.remove();
    window.setTimeout(() => toast.remove(), kShownMs);
  }
}

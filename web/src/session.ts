// Logging in. The console asks who is logged in; when nobody is, it shows the login form, or before the first admin
// exists the setup form, which takes the one-time code shown on the robot's screen. A session is a cookie the daemon
// sets (HttpOnly, SameSite=Strict); the page reloads once it has one.
import { leavePage, send, type SetupStatus } from './api';
import { byId } from './dom';

export type Role = 'viewer' | 'operator' | 'admin';
export interface Me { name: string; role: Role; kind: string; }

const kRank: Record<Role, number> = { viewer: 1, operator: 2, admin: 3 };

export function mayDo(me: Me, needed: Role): boolean {
  return kRank[me.role] >= kRank[needed];
}

// The logged-in user; null when nobody is. Asked of the public setup status, which says who the caller is: a page
// opened before logging in makes no request that fails.
export async function whoAmI(): Promise<Me | null> {
  return (await send<SetupStatus>('GET', '/api/v1/setup')).session;
}

// The logged-in admin, named in the page's #user, for the admin-only pages; anyone else is sent to the console (which
// logs them in) and gets null.
export async function requireAdmin(): Promise<Me | null> {
  const me = await whoAmI();
  if (!me || me.role !== 'admin') {
    location.href = '/';
    return null;
  }
  byId('user').textContent = `${me.name} (${me.role})`;
  return me;
}

// Resolves with the logged-in user; otherwise shows the login (or setup) form and never resolves: the page reloads
// after logging in.
export async function requireSession(): Promise<Me> {
  const setup = await send<SetupStatus>('GET', '/api/v1/setup');
  if (setup.session) return setup.session;
  const dialog = byId<HTMLDialogElement>('login');
  const form = byId<HTMLFormElement>('login-form');
  const error = byId('login-error');
  byId('login-title').textContent = setup.needed ? 'Set up this robot' : 'Log in';
  byId('login-setup').hidden = !setup.needed;
  byId<HTMLInputElement>('login-code').required = setup.needed;
  byId('login-hint').textContent = setup.needed
    ? 'Type the setup code shown on the robot\'s screen (and in its journal) and choose the first admin\'s name and password.'
    : '';
  form.addEventListener('submit', (event) => {
    event.preventDefault();
    const username = byId<HTMLInputElement>('login-username').value;
    const password = byId<HTMLInputElement>('login-password').value;
    const request = setup.needed
      ? send('POST', '/api/v1/setup', { code: byId<HTMLInputElement>('login-code').value, username, password })
      : send('POST', '/api/v1/session', { username, password });
    request.then(() => location.reload()).catch((e: Error) => { error.textContent = e.message; });
  });
  dialog.showModal();
  return new Promise<Me>(() => undefined);
}

// Shows who is logged in, and disables what their role may not do: elements marked data-needs="operator" or "admin".
export function applyRole(me: Me): void {
  byId('user').textContent = `${me.name} (${me.role})`;
  byId('admin-link').hidden = !mayDo(me, 'admin');
  byId('settings-link').hidden = !mayDo(me, 'admin');
  byId('logout').addEventListener('click', () => {
    // Nothing more is asked, and what was asked is answered, before the session ends; then the login form.
    void leavePage()
      .then(() => fetch('/api/v1/session', { method: 'DELETE', cache: 'no-store' }))
      .finally(() => location.reload());
  });
  document.body.dataset.role = me.role;
  applyNeeds(me, document);
}

// Disables the elements under `root` marked with a role (data-needs) that `me` does not have: the page's at login,
// and the rows a panel draws later.
export function applyNeeds(me: Me, root: ParentNode): void {
  for (const element of root.querySelectorAll<HTMLElement>('[data-needs]')) {
    const needed = element.dataset.needs as Role;
    if (mayDo(me, needed)) continue;
    element.classList.add('forbidden');
    element.title = `${element.title ? `${element.title} ` : ''}(needs the ${needed} role)`;
    if ('disabled' in element) (element as HTMLButtonElement).disabled = true;
  }
}

// Whether the user may use `element` (its data-needs role).
export function permitted(element: HTMLElement): boolean {
  return !element.classList.contains('forbidden');
}

// The element with this id, typed; a missing element is a bug in index.html, so it throws.
export function byId<T extends HTMLElement>(id: string): T {
  const element = document.getElementById(id);
  if (!element) throw new Error(`missing #${id}`);
  return element as T;
}

// `text` with HTML's special characters escaped, for markup built from names people typed.
export function escapeHtml(text: string): string {
  return text.replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);
}

// Tells the person at the console what happened: a string for what went as asked, an Error for what did not (shown
// as an error). `undo`, when given, is offered beside the message for as long as it shows.
export type Report = (message: string | Error, undo?: { label: string; run: () => void }) => void;

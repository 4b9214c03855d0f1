// The console's layout at every size (style.css says which): on a phone the header's account and pages are a menu,
// the map tools a menu over the map (closed once a tool is picked, the button naming it), and the panels a sheet at the
// bottom: a row of tabs, the picked tab's panels shown when the sheet is open. On a wider screen the same elements are
// a toolbar and a column of every panel, and these controls are hidden.
import { byId } from './dom';

// A button that opens and closes `panel` (its aria-expanded and the panel's "open" class); a click elsewhere closes it.
function dropdown(button: HTMLElement, panel: HTMLElement): () => void {
  const set = (open: boolean) => {
    panel.classList.toggle('open', open);
    button.setAttribute('aria-expanded', String(open));
  };
  button.addEventListener('click', (event) => {
    event.stopPropagation();
    set(!panel.classList.contains('open'));
  });
  document.addEventListener('click', (event) => {
    if (!panel.contains(event.target as Node)) set(false);
  });
  return () => set(false);
}

export function setUpLayout(): void {
  dropdown(byId('menu-toggle'), byId('menu'));
  const closeTools = dropdown(byId('tools-toggle'), byId('tools'));
  // The sheet: a tab shows its panels and opens the sheet; the open tab again, or the arrow, closes it.
  const panels = byId('panels');
  const toggle = byId('sheet-toggle');
  const open = (on: boolean) => {
    panels.classList.toggle('expanded', on);
    toggle.setAttribute('aria-expanded', String(on));
    toggle.innerHTML = on ? '&#9660;' : '&#9650;';
    if (on) panels.scrollTop = 0;
  };
  const show = (sheet: string) => {
    for (const tab of document.querySelectorAll<HTMLElement>('#sheet-tabs [role=tab]')) {
      tab.setAttribute('aria-selected', String(tab.dataset.sheet === sheet));
    }
    for (const panel of panels.querySelectorAll<HTMLElement>('.panel')) {
      panel.classList.toggle('on-sheet', panel.dataset.sheet === sheet);
    }
  };
  for (const tab of document.querySelectorAll<HTMLElement>('#sheet-tabs [role=tab]')) {
    tab.addEventListener('click', () => {
      const again = tab.getAttribute('aria-selected') === 'true';
      show(tab.dataset.sheet ?? 'mission');
      open(!(again && panels.classList.contains('expanded')));
    });
  }
  toggle.addEventListener('click', () => open(!panels.classList.contains('expanded')));
  show('mission');
  // A tool picked: the menu and the sheet close, so that the map is there to use it on.
  for (const button of document.querySelectorAll<HTMLButtonElement>('#tools button[data-tool]')) {
    button.addEventListener('click', () => {
      byId('tool-name').textContent = button.textContent;
      closeTools();
      open(false);
    });
  }
}

// Whether `element` is on screen now (not in a closed sheet or a hidden tab): what is not seen need not be fetched.
export function shown(element: HTMLElement): boolean {
  return element.offsetParent !== null;
}

// What the layout needs beyond CSS (style.css lays it out): the two show/hide toggles of small screens
// (the bar's Menu, the panel's Status), and the part of the map view the bar and the panel leave uncovered,
// whose centre is where the camera puts the robot when it follows it.

/** Each `.toggle` button shows or hides what it controls (CSS reads its aria-expanded). */
export function setUpToggles() {
  for (const toggle of document.querySelectorAll('button.toggle[aria-controls]')) {
    toggle.addEventListener('click', () => {
      toggle.setAttribute('aria-expanded', String(toggle.getAttribute('aria-expanded') !== 'true'));
    });
  }
  // The menu closes once a choice is made (Colour cycles through its modes, so it stays open for another),
  // when the user turns to the map, or on Escape.
  const menu = document.getElementById('menu-toggle');
  const closeMenu = () => menu.setAttribute('aria-expanded', 'false');
  document.getElementById('bar-tools').addEventListener('click', (event) => {
    const button = event.target.closest('button');
    if (button && button.id !== 'color-mode') closeMenu();
  });
  document.getElementById('view').addEventListener('pointerdown', closeMenu);
  document.addEventListener('keydown', (event) => event.key === 'Escape' && closeMenu());
}

/**
 * The largest rectangle of the window clear of the bar (on top) and the panel: beside the panel where it
 * stands at the right (a wide screen), above it where it lies along the bottom (a phone). Client pixels.
 */
export function uncoveredArea(bar, panel) {
  const width = window.innerWidth;
  const height = window.innerHeight;
  const top = Math.min(Math.max(bar.getBoundingClientRect().bottom, 0), height);
  const p = panel.getBoundingClientRect();
  const beside = { left: 0, top, right: Math.max(p.left, 0), bottom: height };
  const above = { left: 0, top, right: width, bottom: Math.max(Math.min(p.top, height), top) };
  const area = (r) => (r.right - r.left) * (r.bottom - r.top);
  return area(beside) >= area(above) ? beside : above;
}

/** Keeps `view`'s uncovered area up to date as the bar and the panel change size (wrap, fold, grow). */
export function trackUncoveredArea(view, bar, panel) {
  const update = () => view.setUncoveredArea(uncoveredArea(bar, panel));
  const observer = new ResizeObserver(update);
  for (const element of [bar, panel, document.documentElement]) observer.observe(element);
  window.addEventListener('resize', update);
  update();
}

"""What the page needs for a screen reader and WCAG 2.1 AA that viser 1.1.1's client does not give.

viser renders every control through ``ViserInputComponent`` (its ``client/src/components/common.tsx``):
a ``<label for=uuid>`` whose ``for`` names a wrapper ``div``, not the input, so a number box, a slider
thumb (Mantine renders it with ``aria-label=""``) and a read-only readout have no accessible name; its
icon buttons have their name only in a tooltip, its logo no ``alt``, its progress bar no label, and
Mantine's filled buttons put white on ``#228be6`` (3.56:1). The client's source is pinned with viser, so
the page is patched from the server: :data:`PATCH` is HTML for viser's Html element (which renders raw
HTML: ``client/src/components/Html.tsx``) holding

* a ``<style>``: the filled buttons' blue darkened to Mantine's blue 8 (``#1971c2``, 5.02:1 under white),
  the plots' titles and legends at :data:`app.panel.look.MIN_TEXT_PX`, a focus ring (:data:`FOCUS`) on
  every focused control;
* keyboard shortcuts (:data:`KEYS`) that click the panel's own buttons when the focus is not in a text
  field, a slider or a dropdown (a presentation clicker sends Page Down/Up or the arrows, which step a
  lecture when one is loaded), Page Up/Down on a slider (ten steps; Mantine's slider ignores them), and
  viser's folder titles made buttons (Tab, Enter, Space, ``aria-expanded``);
* a script (:data:`SCRIPT`), which an inserted ``<script>`` element would not run (``innerHTML`` never
  does), started once per page by an image that fails to load (``onerror``). It watches the page and
  gives each control the name of its visible label (``aria-labelledby``), names icon buttons after
  their icon (viser's tooltip text) and the notification's close button, gives viser's logo the
  ``alt`` of its link's title, names a progress bar after the text above it (the sleeping gauge), gives
  the 3D view (three.js's canvas) ``role="img"`` and a name that says what it shows (the motion in words),
  and moves ``aria-live`` of the motion in words onto the element React keeps across updates, so each
  new text is announced.

Every step is idempotent and only adds what is missing; tests/browser/test_accessibility.py scans the
result with axe-core. What each patch answers is listed in docs/accessibility.md.
"""

from __future__ import annotations

import html

from app.language.words import joined, keep, mark, say

PAGE_WORDS = (
    mark("Pause"),
    mark("Play"),
    mark("Step"),
    mark("Step back"),
    mark("Reset"),
    mark("Next"),
    mark("Previous"),
    mark("Configuration and diagnostics"),
    mark("Return to the controls"),
    mark("Commands"),
    mark("Share"),
    mark("Close the notification"),
    mark("3D view of the simulation"),
    mark("button"),
)
"""The words :data:`SCRIPT` writes (names for viser's unnamed buttons and the 3D view) or looks for (the
buttons its shortcuts press), in English: each page receives their translations in its language marker
(:func:`app.guards.language.lang_marker`)."""

__all__ = ["PAGE_WORDS", "FILLED_BLUE", "FOCUS", "KEYS", "PATCH", "SCRIPT", "keys_markdown"]

KEYS = (
    ("Space", mark("play or pause")),
    ("→ or .", mark("one step (paused); in a lecture → is the next step and . the clock's step")),
    ("← or ,", mark("one step back (paused); in a lecture ← is the previous step and , the clock's step back")),
    ("Shift+← / Shift+→", mark("the timeline one second back / on (paused)")),
    ("R", mark("reset to t = 0")),
    (
        "Page Down / Page Up, ↓ / ↑, → / ←",
        mark("next / previous lecture step (what a presentation clicker sends), when a lecture is loaded"),
    ),
    ("Tab / Shift+Tab", mark("the next / previous control; sliders take ← → ↑ ↓, Page Up/Down, Home/End")),
    ("Enter or Space", mark("on a folder's title (Clock, State, Export, Keyboard): open or close it")),
)
"""The keyboard map shown in the panel's Keyboard folder. The shortcuts are not taken while the focus is in
a text field, a slider or a dropdown (which use these keys themselves), nor Space on a focused button
(which presses that button)."""


def keys_markdown() -> str:
    """The keyboard map as markdown for the panel."""
    # A markup template (not for the translators): each line's words are the catalogs'.
    return keep(joined([say("- **{key}**: {what}", key=key, what=what) for key, what in KEYS], "\n"))


FILLED_BLUE = ("#1971c2", "#1864ab")
"""Mantine's blue 8 and 9: the filled buttons' background and its hover (white on them: 5.02:1, 6.09:1)."""

FOCUS = ("#1971c2", "#4dabf7")
"""The focus ring (2 px, 2 px off the control) in the light and the dark look: Mantine's blue 8 on white
(5.02:1) and blue 4 on the dark panel (6.2:1 on #242424); WCAG 2.4.7 and 1.4.11 (3:1)."""

SCRIPT = r"""(() => {
  if (window.rblAccess) return;
  window.rblAccess = true;
  const ICONS = {adjustments: 'Configuration and diagnostics', 'arrow-back': 'Return to the controls',
                 'list-search': 'Commands', share: 'Share'};
  for (const icon in ICONS) ICONS[icon] = [ICONS[icon]];
  const CONTROLS = 'input:not([type=hidden]), textarea, select, [role=slider], [role=combobox]';
  // The page's language and its words (app.guards.language.lang_marker): the marker each browser receives
  // in its own language names it, and carries the translations of the words this script writes or seeks.
  const marker = () => document.querySelector('[data-rbl-lang]');
  const said = (english) => {
    const m = marker();
    try { return (m && JSON.parse(m.getAttribute('data-rbl-words') || '{}')[english]) || english; }
    catch (err) { return english; }
  };
  const text = (el) => (el ? el.textContent || '' : '').replace(/\s+/g, ' ').trim();
  const named = (el) => text({textContent: el.getAttribute('aria-label') || ''}) !== ''
    || !!(el.getAttribute('aria-labelledby') && document.getElementById(el.getAttribute('aria-labelledby')))
    || (el.labels && el.labels.length > 0);
  const set = (el, name, value) => { if (el.getAttribute(name) !== value) el.setAttribute(name, value); };
  function fix() {
    const m = marker();
    if (m && document.documentElement.lang !== m.getAttribute('data-rbl-lang'))
      document.documentElement.lang = m.getAttribute('data-rbl-lang');
    for (const label of document.querySelectorAll('label[for]')) {
      const row = label.closest('.mantine-Flex-root');
      if (!row) continue;
      set(label, 'id', 'rbl-label-' + label.getAttribute('for'));
      for (const el of row.querySelectorAll(CONTROLS)) {
        if (!(el.labels && el.labels.length) && !text({textContent: el.getAttribute('aria-label') || ''}))
          set(el, 'aria-labelledby', label.id);
      }
    }
    for (const b of document.querySelectorAll('button, [role=button]')) {
      if (text(b) || named(b) || b.getAttribute('title')) continue;
      if (b.closest('.mantine-Notification-root')) { set(b, 'aria-label', said('Close the notification')); continue; }
      const icon = b.querySelector('svg[class*="tabler-icon-"]');
      const key = icon ? [...icon.classList].find(c => c.startsWith('tabler-icon-') && c.length > 12) : null;
      const name = key ? key.slice(12) : '';
      set(b, 'aria-label', ICONS[name] ? said(ICONS[name][0]) : (name ? name.replace(/-/g, ' ') : said('button')));
    }
    for (const img of document.querySelectorAll('img:not([alt])')) {
      const link = img.closest('a[title]');
      img.setAttribute('alt', link ? link.getAttribute('title') : '');
    }
    for (const bar of document.querySelectorAll('[role=progressbar]')) {
      if (named(bar)) continue;
      let box = bar, name = '';
      for (let up = 0; up < 8 && box && !name; up++, box = box.parentElement) {
        const prev = box.previousElementSibling;
        name = prev ? text(prev.querySelector('strong') || prev) : '';
      }
      if (name) set(bar, 'aria-label', name);
    }
    // viser's folder titles are clickable divs: a button for the keyboard and a screen reader too.
    for (const title of document.querySelectorAll('.mantine-Paper-root[data-with-border] > .mantine-Paper-root:first-child')) {
      if (!text(title)) continue;
      title.classList.add('rbl-folder');
      set(title, 'role', 'button');
      set(title, 'tabindex', '0');
      set(title, 'aria-expanded', title.querySelector('.tabler-icon-chevron-up') ? 'true' : 'false');
    }
    const words = document.querySelector('.rbl-motion');
    if (words) {
      const keep = words.parentElement;
      set(keep, 'aria-live', 'polite');
      set(keep, 'aria-atomic', 'true');
      words.removeAttribute('aria-live');
    }
    const view = document.querySelector('canvas[data-engine]');
    if (view) {
      set(view, 'role', 'img');
      set(view, 'aria-label', said('3D view of the simulation') + (text(words) ? ': ' + text(words) : ''));
    }
  }
  // Shortcuts (KEYS): the panel's own buttons clicked, so a key does exactly what the button does (and is
  // refused on the server just the same for a follower). A lecture is loaded when its Next button is
  // shown: then the arrows step the lecture, as a clicker that sends arrows expects, and '.' the clock.
  const KEYS = {' ': ['Pause', 'Play'], '.': ['Step'], ',': ['Step back'], r: ['Reset'], R: ['Reset'],
                PageDown: ['Next'], PageUp: ['Previous'], ArrowDown: ['Next'], ArrowUp: ['Previous']};
  const TYPING = 'input, textarea, select, [contenteditable=true], [role=slider], [role=combobox], '
    + '[role=listbox], [role=option], [role=dialog], [role=menu]';
  const shown = (names) => {
    const any = names.flatMap(n => [n, said(n)]);  // a button's English name, or the page's language's
    return [...document.querySelectorAll('button')].find(b => any.includes(text(b)) && b.offsetParent);
  };
  document.addEventListener('keydown', (e) => {
    const target = e.target.closest ? e.target : document.body;
    if (target.closest('.rbl-folder') && (e.key === 'Enter' || e.key === ' ')) {
      e.preventDefault();
      target.closest('.rbl-folder').click();
      return;
    }
    // Mantine's slider takes the arrows, Home and End but not Page Up/Down (WAI-ARIA's larger step): ten
    // steps, within the slider's range.
    const thumb = target.closest('[role=slider]');
    if (thumb && (e.key === 'PageUp' || e.key === 'PageDown') && !e.altKey && !e.ctrlKey && !e.metaKey) {
      e.preventDefault();
      // One arrow press gives the step; the value ten steps on (within the range) goes in the slider's number
      // box, as typed, so the server gets one value (presses in a row would race the server's echo).
      const arrow = e.key === 'PageUp' ? 'ArrowUp' : 'ArrowDown';
      const num = (name) => parseFloat(thumb.getAttribute(name));
      const before = num('aria-valuenow');
      thumb.dispatchEvent(new KeyboardEvent('keydown', {key: arrow, code: arrow, bubbles: true, cancelable: true}));
      requestAnimationFrame(() => {
        const step = num('aria-valuenow') - before;
        const row = thumb.closest('.mantine-Flex-root');
        const box = row && row.querySelector('.mantine-NumberInput-input');
        if (!step || !box) return;
        const target = Math.min(num('aria-valuemax'), Math.max(num('aria-valuemin'), before + 10 * step));
        const digits = Math.max(0, -Math.floor(Math.log10(Math.abs(step)) + 1e-9));
        const typed = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, 'value').set;
        typed.call(box, target.toFixed(digits));
        box.dispatchEvent(new Event('input', {bubbles: true}));
        thumb.focus({preventScroll: true});  // the number box takes the focus as it is typed into
        setTimeout(() => { if (document.activeElement === box) thumb.focus({preventScroll: true}); }, 50);
      });
      return;
    }
    if (e.altKey || e.ctrlKey || e.metaKey || target.closest(TYPING)) return;
    if (e.key === ' ' && target.closest('button, [role=button], a')) return;  // presses what has the focus
    // Shift+←/→: the timeline's jump of a second; ←/→ a lecture's steps when one is shown, else the clock's.
    const jump = e.shiftKey && {ArrowLeft: ['\u22121 s'], ArrowRight: ['+1 s']}[e.key];
    const names = jump || (e.key === 'ArrowRight' ? (shown(['Next']) ? ['Next'] : ['Step'])
      : e.key === 'ArrowLeft' ? (shown(['Previous']) ? ['Previous'] : ['Step back']) : KEYS[e.key]);
    if (!names) return;
    const button = shown(names);
    if (!button) return;
    e.preventDefault();
    if (!button.disabled && !button.hasAttribute('data-disabled')) button.click();
  });
  let queued = false;
  new MutationObserver(() => {
    if (!queued) { queued = true; setTimeout(() => { queued = false; fix(); }, 20); }
  }).observe(document.body, {childList: true, subtree: true, characterData: true});
  fix();
})();"""

STYLE = f"""<style>
:root, :root[data-mantine-color-scheme] {{
  --mantine-primary-color-filled: {FILLED_BLUE[0]} !important;
  --mantine-primary-color-filled-hover: {FILLED_BLUE[1]} !important; }}
.u-title, .u-legend, .u-legend * {{ font-size: 14px !important; }}
/* viser's button groups are Mantine's outline buttons, light blue on white (3.56:1): the focus blue. */
.mantine-Button-root[data-variant=outline] {{ --button-color: var(--rbl-focus) !important;
  --button-bd: 1px solid var(--rbl-focus) !important; }}
:root {{ --rbl-focus: {FOCUS[0]}; }}
:root[data-mantine-color-scheme=dark] {{ --rbl-focus: {FOCUS[1]}; }}
:focus-visible, .mantine-Input-input:focus, [role=slider]:focus {{
  outline: 2px solid var(--rbl-focus) !important; outline-offset: 2px !important; }}
</style>"""

PATCH = (
    STYLE
    + f'<script type="text/plain" class="rbl-access">{SCRIPT}</script>'
    + '<img alt="" hidden src="data:," onerror="'
    + html.escape("if (!window.rblAccess) (0, eval)(document.querySelector('.rbl-access').textContent)")
    + '">'
)
"""The patch, for an Html element of the panel (:func:`app.panel.look.configure` adds it)."""

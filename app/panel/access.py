"""What the page needs for a screen reader and WCAG 2.1 AA that viser 1.1.1's client does not give.

viser renders every control through ``ViserInputComponent`` (its ``client/src/components/common.tsx``):
a ``<label for=uuid>`` whose ``for`` names a wrapper ``div``, not the input, so a number box, a slider
thumb (Mantine renders it with ``aria-label=""``) and a read-only readout have no accessible name; its
icon buttons have their name only in a tooltip, its logo no ``alt``, its progress bar no label, and
Mantine's filled buttons put white on ``#228be6`` (3.56:1). The client's source is pinned with viser, so
the page is patched from the server: :data:`PATCH` is HTML for viser's Html element (which renders raw
HTML: ``client/src/components/Html.tsx``) holding

* a ``<style>``: the filled buttons' blue darkened to Mantine's blue 8 (``#1971c2``, 5.02:1 under white),
  the plots' titles and legends at :data:`app.panel.look.MIN_TEXT_PX`;
* keyboard shortcuts (:data:`KEYS`) that click the panel's own buttons when the focus is not in a
  control or a text field (a presentation clicker sends PageDown and PageUp);
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

__all__ = ["FILLED_BLUE", "KEYS", "PATCH", "SCRIPT", "keys_markdown"]

KEYS = (
    ("Space", "play or pause"),
    ("→", "one step (paused)"),
    ("R", "reset to t = 0"),
    ("Page Down / Page Up", "next / previous lecture step (what a presentation clicker sends)"),
    ("Tab / Shift+Tab", "the next / previous control; sliders take ← → ↑ ↓, Page Up/Down, Home/End"),
)
"""The keyboard map shown in the panel's Keyboard folder (the shortcuts are not taken while the focus is
in a control or a text field)."""


def keys_markdown() -> str:
    """The keyboard map as markdown for the panel."""
    return "\n".join(f"- **{key}**: {what}" for key, what in KEYS)


FILLED_BLUE = ("#1971c2", "#1864ab")
"""Mantine's blue 8 and 9: the filled buttons' background and its hover (white on them: 5.02:1, 6.09:1)."""

SCRIPT = r"""(() => {
  if (window.rblAccess) return;
  window.rblAccess = true;
  const ICONS = {adjustments: 'Configuration and diagnostics', 'arrow-back': 'Return to the controls',
                 'list-search': 'Commands', share: 'Share'};
  const CONTROLS = 'input:not([type=hidden]), textarea, select, [role=slider], [role=combobox]';
  const text = (el) => (el ? el.textContent || '' : '').replace(/\s+/g, ' ').trim();
  const named = (el) => text({textContent: el.getAttribute('aria-label') || ''}) !== ''
    || !!(el.getAttribute('aria-labelledby') && document.getElementById(el.getAttribute('aria-labelledby')))
    || (el.labels && el.labels.length > 0);
  const set = (el, name, value) => { if (el.getAttribute(name) !== value) el.setAttribute(name, value); };
  function fix() {
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
      if (b.closest('.mantine-Notification-root')) { set(b, 'aria-label', 'Close the notification'); continue; }
      const icon = b.querySelector('svg[class*="tabler-icon-"]');
      const key = icon ? [...icon.classList].find(c => c.startsWith('tabler-icon-') && c.length > 12) : null;
      const name = key ? key.slice(12) : '';
      set(b, 'aria-label', ICONS[name] || (name ? name.replace(/-/g, ' ') : 'button'));
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
      set(view, 'aria-label', '3D view of the simulation' + (text(words) ? ': ' + text(words) : ''));
    }
  }
  // Shortcuts (KEYS): the panel's own buttons clicked, so a key does exactly what the button does (and is
  // refused on the server just the same for a follower); never while typing or on a focused control.
  const KEYS = {' ': ['Pause', 'Play'], ArrowRight: ['Step'], r: ['Reset'], R: ['Reset'],
                PageDown: ['Next'], PageUp: ['Previous']};
  const TYPING = 'input, textarea, select, button, [contenteditable=true], [role=slider], [role=combobox], '
    + '[role=listbox], [role=option], [role=dialog]';
  document.addEventListener('keydown', (e) => {
    const names = KEYS[e.key];
    if (!names || e.altKey || e.ctrlKey || e.metaKey || (e.target.closest && e.target.closest(TYPING))) return;
    const button = [...document.querySelectorAll('button')].find(
      b => names.includes(text(b)) && !b.disabled && !b.hasAttribute('data-disabled') && b.offsetParent);
    if (!button) return;
    e.preventDefault();
    button.click();
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
</style>"""

PATCH = (
    STYLE
    + f'<script type="text/plain" class="rbl-access">{SCRIPT}</script>'
    + '<img alt="" hidden src="data:," onerror="'
    + html.escape("if (!window.rblAccess) (0, eval)(document.querySelector('.rbl-access').textContent)")
    + '">'
)
"""The patch, for an Html element of the panel (:func:`app.panel.look.configure` adds it)."""

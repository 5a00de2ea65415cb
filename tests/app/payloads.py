"""Cross-site-scripting payloads in the manner of OWASP's filter-evasion cheat sheet, each of which sets
``window.__pwned`` if a page runs it: the corpus the text paths are tested with (unit and browser tests).

Tags with event handlers, ``iframe srcdoc``, ``javascript:`` links in HTML and in Markdown, Markdown
images, entity-encoded and mixed-case tags, broken quoting, comments and nested tags.
"""

from __future__ import annotations

__all__ = ["PAYLOADS", "PWN"]

PWN = "window.__pwned=1"
"""What every payload tries to run."""

PAYLOADS: tuple[str, ...] = (
    f"<img src=x onerror={PWN}>",
    f'<IMG SRC=x OnErRoR="{PWN}">',
    f"<svg onload={PWN}>",
    f"<svg/onload={PWN}>",
    f"<body onload={PWN}>",
    f"<script>{PWN}</script>",
    f"<ScRiPt>{PWN}</sCrIpT>",
    '<iframe srcdoc="&lt;script&gt;parent.__pwned=1&lt;&#47;script&gt;">x.stl',
    '<iframe src="javascript:parent.__pwned=1">',
    f'<a href="javascript:{PWN}">click</a>',
    f'<a href="jav&#x09;ascript:{PWN}">click</a>',
    f'<a href="&#106;&#97;&#118;&#97;&#115;&#99;&#114;&#105;&#112;&#116;&#58;{PWN}">click</a>',
    f"[click](javascript:{PWN})",
    f"[click](JaVaScRiPt:{PWN})",
    f"![x](javascript:{PWN})",
    f'![x](x" onerror="{PWN})',
    f"&lt;img src=x onerror={PWN}&gt;",
    f"&#60;img src=x onerror={PWN}&#62;",
    f'<details open ontoggle="{PWN}">',
    f'<div style="width:100px;height:100px" onmouseover="{PWN}">x</div>',
    f'<input autofocus onfocus="{PWN}">',
    f"<video><source onerror={PWN}></video>",
    f'<object data="javascript:{PWN}"></object>',
    f'<math><mtext><table><mglyph><style><img src=x onerror="{PWN}">',
    f"<<img src=x onerror={PWN}>//<",
    f'"><img src=x onerror={PWN}>',
    f"'><svg onload={PWN}>",
    f"<!--><img src=x onerror={PWN}>-->",
    f"**bold** <b onclick={PWN}>b</b> `<img src=x onerror={PWN}>`",
    f"<scr<script>ipt>{PWN}</scr</script>ipt>",
)

"""The replay's legend, a small fixed panel over the viewer naming each overlay's colour, and a
tidy controls tree: each overlay one checkbox, the children the recording animates (snapshots,
marks, Meshcat's `<object>` nodes) kept out of the viewer's controls.

Both are written into the static HTML page; the controls are tidied after every command the
viewer handles, since the page hands it the recording's commands asynchronously.
"""

from __future__ import annotations

import html
import json
from collections.abc import Sequence

from hsr_handover.replay.overlays import OVERLAYS, Overlay, swatch_css

LEGEND_ID = "overlay-legend"
_STYLE = """
  <style>
    #overlay-legend {
      position: fixed; left: 8px; bottom: 8px; z-index: 10; max-width: 46vw;
      font: 11px/1.35 sans-serif; color: #222; background: rgba(255, 255, 255, 0.82);
      border-radius: 4px; padding: 4px 8px; pointer-events: auto;
    }
    #overlay-legend summary { cursor: pointer; font-weight: bold; }
    #overlay-legend ul { list-style: none; margin: 2px 0 0; padding: 0; }
    #overlay-legend .swatch {
      display: inline-block; width: 18px; height: 9px; margin-right: 5px;
      vertical-align: middle; border: 1px solid rgba(0, 0, 0, 0.25);
    }
    #overlay-legend .where { color: #555; margin-top: 2px; }
  </style>"""
_TIDY = """
  <script>
    (function () {
      var layers = %s;
      function child(node, name) { return node && node.children[name]; }
      function tidy() {
        layers.forEach(function (path) {
          var node = path.reduce(child, viewer.scene_tree);
          if (!node) { return; }
          Object.keys(node.children).forEach(function (name) {
            var item = node.children[name].folder.domElement.parentElement;
            if (item) { item.style.display = "none"; }
          });
        });
      }
      var pending = false;
      var handle = viewer.handle_command.bind(viewer);
      viewer.handle_command = function (command) {
        handle(command);
        if (!pending) {
          pending = true;
          setTimeout(function () { pending = false; tidy(); }, 0);
        }
      };
      tidy();
    })();
  </script>"""


def legend_html(overlays: Sequence[Overlay]) -> str:
    """The legend's panel for `overlays`, each its colour and what it shows."""
    rows = "".join(
        f'<li data-overlay="{html.escape(o.name)}"><span class="swatch" '
        f'style="background: {swatch_css(o)}"></span>{html.escape(o.label)}</li>'
        for o in overlays
    )
    where = f"Switch each on or off under Scene &#9656; {OVERLAYS.strip('/')} in the controls."
    return (
        f'\n  <div id="{LEGEND_ID}"><details open><summary>What the robot thinks</summary>'
        f'<ul>{rows}</ul><div class="where">{where}</div></details></div>'
    )


def tidy_script(overlays: Sequence[Overlay]) -> str:
    """The script that keeps each overlay's children out of the viewer's controls."""
    layers = [overlay.path.strip("/").split("/") for overlay in overlays]
    return _TIDY % json.dumps(layers)


def with_legend(page: str, overlays: Sequence[Overlay]) -> str:
    """Meshcat's static page with the legend and the tidy controls for `overlays` (the page
    unchanged when there are none)."""
    if not overlays:
        return page
    end = page.rindex("</body>")
    added = _STYLE + legend_html(overlays) + tidy_script(overlays)
    return page[:end] + added + "\n" + page[end:]

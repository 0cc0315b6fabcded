"""One look for every HTML page of the project (replay, fleet dashboard, diagnosis).

* :mod:`.render`: the Jinja2 templates (``templates/``) and the one stylesheet (``style.css``),
  inlined into each page so that a page is one self-contained file (no network: Plotly's
  JavaScript is inlined too, from the ``plotly`` package);
* :mod:`.humanize`: numbers in the units people read (mm, µm, kN, hours/days), the status lights;
* :mod:`.life`: the "how worn, when due, how sure" view of a remaining-life entry;
* :mod:`.figures`: Plotly figures (plain JSON dicts) shared by the replay report and the dashboard.

The JSON outputs keep SI units; only these pages convert.
"""

from typing import Any

__all__ = ["render_page"]


def __getattr__(name: str) -> Any:
    """``render_page`` on first use: the node imports :mod:`.life` and :mod:`.humanize` only, never
    Jinja2 or Plotly (PEP 562)."""
    if name == "render_page":
        from ebm_wear_monitor.reports.render import render_page
        return render_page
    raise AttributeError(name)

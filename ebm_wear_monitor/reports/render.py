"""Rendering: the Jinja2 templates of ``templates/`` with the one stylesheet ``style.css`` inlined.

Every page is a single file that opens without network access: the stylesheet is inlined, and a
page with interactive figures inlines Plotly's JavaScript (``plotly.min.js`` as shipped in the
``plotly`` package, about 4.8 MB) once.
"""

from __future__ import annotations

import functools
from datetime import datetime, timezone
from importlib import resources

import jinja2

from ebm_wear_monitor import __version__
from ebm_wear_monitor.reports import humanize


@functools.cache
def _environment() -> jinja2.Environment:
    env = jinja2.Environment(loader=jinja2.PackageLoader("ebm_wear_monitor.reports", "templates"),
                             autoescape=jinja2.select_autoescape(["html"]), undefined=jinja2.StrictUndefined,
                             trim_blocks=True, lstrip_blocks=True)
    env.filters.update(mm=humanize.mm, um=humanize.um, kn=humanize.kn, count=humanize.count,
                       duration=humanize.duration, percent=humanize.percent)
    env.globals.update(status=humanize.status, NA=humanize.NA, known=humanize.known)
    return env


@functools.cache
def stylesheet() -> str:
    """The one stylesheet of every report."""
    return resources.files("ebm_wear_monitor.reports").joinpath("style.css").read_text(encoding="utf-8")


@functools.cache
def plotly_js() -> str:
    """Plotly's JavaScript, to inline (no network access needed to open the page)."""
    from plotly.offline import get_plotlyjs

    return get_plotlyjs()


def render_page(template: str, title: str, *, subtitle: str = "", plotly: bool = False, **context: object
                ) -> str:
    """A complete HTML page from ``templates/<template>`` (which extends ``base.html``)."""
    generated = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return _environment().get_template(template).render(
        title=title, subtitle=subtitle, css=stylesheet(), plotly_js=plotly_js() if plotly else "",
        generated=generated, version=__version__, **context)

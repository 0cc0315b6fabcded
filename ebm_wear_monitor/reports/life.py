"""The people's view of one unit's remaining life: how worn, when due, how sure.

Built from the section 4 ``remaining_life`` entry (keys declared in
:mod:`ebm_wear_monitor.schema.monitor`: ``status``, ``cycles_p05/p50/p95``, ``seconds_p05/p50/p95``,
``usage_span_s``, ``applications_per_hour``, ``limit_m``; older entries carry ``hours_p50`` only)
and the ``clearance`` entry. A key that is absent or null is shown as "not available", never estimated here.
"""

from __future__ import annotations

from dataclasses import dataclass

from ebm_wear_monitor.reports.humanize import DAY_S, NA, count, duration, known, mm, percent, status


@dataclass(frozen=True)
class LifeView:
    """Text of one unit's remaining life, ready for a template."""

    status: str  # status name (ok | warn | due | insufficient_data | failed)
    status_words: str
    status_class: str  # CSS class of the light
    clearance: str  # estimate ± 1 sigma, mm
    limit: str  # mm
    fraction: float | None  # clearance estimate / limit [-]
    fraction_text: str
    applications: str  # "p50 22 (p05 18 – p95 28) applications"
    calendar: str  # the same in hours/days at the observed usage
    usage: str  # "3,220 applications per hour, observed over 0.2 h"
    caveat: str  # non-empty when the calendar time rests on too little observed usage

    def line(self) -> str:
        """One line for a terminal or a log (replay, fleet and the node print the same)."""
        text = f"{self.status_words}: {self.applications}"
        if self.calendar != NA:
            text += f"; {self.calendar} at {self.usage}"
        if self.caveat:
            text += " (usage observed over less than a day: calendar time uncertain)"
        return text


def _calendar(rl: dict) -> str:
    secs = {q: rl.get(f"seconds_{q}") for q in ("p05", "p50", "p95")}
    if not known(secs["p50"]) and known(rl.get("hours_p50")):
        secs["p50"] = rl["hours_p50"] * 3600.0
    if not known(secs["p50"]):
        return NA
    band = (f" (p05 {duration(secs['p05'])} – p95 {duration(secs['p95'])})"
            if known(secs["p05"]) and known(secs["p95"]) else "")
    return f"{duration(secs['p50'])}{band}"


def life_view(remaining_life: dict, clearance: dict, state: str | None = None) -> LifeView:
    """The view of one unit; ``state`` overrides the status (the fleet's ``failed``)."""
    rl = remaining_life or {}
    name = state or rl.get("status") or "insufficient_data"
    words, css = status(name)
    est, std, limit = clearance.get("estimate_m"), clearance.get("std_m"), rl.get("limit_m")
    fraction = est / limit if known(est) and known(limit) and limit > 0 else None
    p = {q: rl.get(f"cycles_{q}") for q in ("p05", "p50", "p95")}
    if known(p["p50"]):
        # p95 null with p50 known: the unit may never reach the limit (growth not resolved from the noise)
        p95 = count(p["p95"]) if known(p["p95"]) else "unbounded"
        applications = f"{count(p['p50'])} applications (p05 {count(p['p05'])} – p95 {p95})"
    else:
        applications = "no measurable clearance growth yet: no remaining life to give"
    rate, span = rl.get("applications_per_hour"), rl.get("usage_span_s")
    usage = f"{rate:.3g} applications per hour" if known(rate) else NA
    usage += f", observed over {duration(span)}" if known(span) else ", observed span not available"
    caveat = ""
    if known(p["p50"]):
        if known(span) and span < DAY_S:
            caveat = (f"The usage was observed over only {duration(span)}: the calendar time assumes the "
                      "unit keeps braking at that rate, which a day's timetable may not.")
        elif not known(span):
            caveat = ("How long the usage was observed is not available: read the calendar time as a "
                      "rough guide.")
    return LifeView(name, words, css, f"{mm(est)} ± {mm(std)}" if known(est) else NA, mm(limit), fraction,
                    percent(fraction), applications, _calendar(rl) if known(p["p50"]) else NA, usage, caveat)

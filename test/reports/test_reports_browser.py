"""Every HTML report in a real headless Chromium: loads with no network and no console error, its
figures render, the dashboard sorts, filters and drills down; a screenshot of each is written
(issue 13 deliverables 2 and 3)."""

from __future__ import annotations

import json
import math

import pandas as pd
import pytest

from ebm_wear_monitor.cli.main import main


def _assert_clean(opened, what: str) -> None:
    assert opened.errors == [], f"{what}: console errors {opened.errors}"
    assert opened.blocked == [], f"{what}: tried the network {opened.blocked}"


def test_replay_report(repo, tmp_path, open_page):
    report = tmp_path / "replay"
    params = str(repo / "bags" / "accelerated_unit.yaml")
    assert main(["replay", str(repo / "bags" / "worn"), "--params", params, "--report", str(report), "--json",
                 str(tmp_path / "r.json"), "--no-progress"]) == 0
    assert [p.name for p in report.iterdir()] == ["index.html"]  # one self-contained file
    opened = open_page(report / "index.html")
    page = opened.page
    page.wait_for_selector(".js-plotly-plot .main-svg")
    _assert_clean(opened, "replay report")
    assert page.locator(".js-plotly-plot").count() == 3  # clearance, remaining life, wear (no faults here)
    entry = json.loads((tmp_path / "r.json").read_text())["units"][0]
    text = page.inner_text("main")
    rl = entry["remaining_life"]
    p05, p50, p95 = (round(rl[f"cycles_{q}"]) for q in ("p05", "p50", "p95"))
    assert f"{p50} applications (p05 {p05} – p95 {p95})" in text
    assert f"{entry['clearance']['estimate_m'] * 1e3:.3f} mm" in text  # mm for people, m in the JSON
    assert "None: every sample was usable." in text and "alpha_ph" not in text
    # the clearance figure: observations drawn last (on top), projection reaching the limit
    fig = page.evaluate("document.querySelector('#clearance-1').data.map(t => [t.name, t.y.length])")
    assert fig[-1][0] == "observed in the application" and fig[-1][1] == entry["duty_cycles"]
    assert any(name.startswith("projection p50") for name, _ in fig)
    rul_axis = page.evaluate("document.querySelector('#rul-1').layout.yaxis.type")
    assert rul_axis == "linear"  # 18..46 applications: less than a decade
    page.screenshot(path=str(tmp_path / "replay.png"), full_page=True)
    assert (tmp_path / "replay.png").stat().st_size > 50_000


@pytest.fixture(scope="module")
def fleet(tmp_path_factory):
    """A generated fleet of 5 units processed on a local Dask cluster: (out dir, units table)."""
    root = tmp_path_factory.mktemp("dash")
    out = root / "out"
    assert main(["fleet", str(root / "fleet"), "--generate", "5", "--cycles-per-bag", "10", "--bags-per-unit",
                 "1", "--workers", "2", "--out", str(out), "--no-progress"]) == 0
    return out, pd.read_parquet(out / "units.parquet")


def test_fleet_dashboard_sorts_filters_and_drills_down(fleet, tmp_path, open_page):
    out, units = fleet
    opened = open_page(out / "report" / "index.html")
    page = opened.page
    page.wait_for_selector("table.units tbody tr")
    _assert_clean(opened, "dashboard")
    rows = page.locator("table.units tbody tr")
    assert rows.count() == len(units)
    shown = [rows.nth(i).get_attribute("data-unit") for i in range(rows.count())]
    assert shown == list(units["unit"])  # the page's order is the parquet's ranking
    # sort by p05 remaining life (column 8): ascending, unknowns last; then descending
    header = page.locator("table.units th").nth(7)
    header.click()
    p05 = units.set_index("unit")["cycles_p05"]
    order = [rows.nth(i).get_attribute("data-unit") for i in range(rows.count())]
    values = [p05[u] for u in order]
    known = [v for v in values if not math.isnan(v)]
    assert known == sorted(known) and all(math.isnan(v) for v in values[len(known):])
    header.click()
    order = [rows.nth(i).get_attribute("data-unit") for i in range(rows.count())]
    known = [p05[u] for u in order if not math.isnan(p05[u])]
    assert known == sorted(known, reverse=True)
    assert header.get_attribute("aria-sort") == "descending"
    # filter by text
    target = units["unit"].iloc[0].split("/")[1]  # a car
    page.fill("#filter", target)
    visible = [u for u in order if page.locator(f"tr[data-unit='{u}']").is_visible()]
    assert visible and all(target in u for u in visible)
    assert len(visible) == sum(target in u for u in units["unit"])
    page.fill("#filter", "")
    # drill-down: the unit with the lowest p05 shows its clearance history with the projection
    urgent = units.dropna(subset=["cycles_p05"]).sort_values("cycles_p05")["unit"].iloc[0]
    page.click(f"tr[data-unit='{urgent}']")
    page.wait_for_selector("#dd-clearance .main-svg")
    assert page.inner_text("#dd-title") == urgent
    names = page.evaluate("document.getElementById('dd-clearance').data.map(t => t.name)")
    assert names[-1] == "observed in the application" and any(n.startswith("projection p50") for n in names)
    row = units.set_index("unit").loc[urgent]
    assert f"{round(row['cycles_p50'])} applications" in page.inner_text("#dd-life")
    _assert_clean(opened, "dashboard after the clicks")
    page.screenshot(path=str(tmp_path / "dashboard.png"), full_page=True)
    assert (tmp_path / "dashboard.png").stat().st_size > 50_000


def test_diagnose_report(repo, tmp_path, open_page):
    report = tmp_path / "diag"
    assert main(["diagnose", str(repo / "bags" / "healthy"), "--params", "embu_000", "--report", str(report),
                 "--no-progress"]) == 0
    opened = open_page(report / "index.html")
    page = opened.page
    _assert_clean(opened, "diagnose report")
    page.wait_for_selector(".js-plotly-plot .main-svg")
    # residuals per phase, gap closed per effect, torque against the screw position (the open-set test runs
    # on this recording: its 8.5 s hold enough moving blocks of determined friction on each side)
    assert page.locator(".js-plotly-plot").count() == 3
    # the verdict in words, the effect table with sizes against floors, the estimated conventions
    assert page.locator(".card .status").first.inner_text().strip()
    assert page.locator("text=floor").count() >= 1 and page.locator("text=force-sensor lag").count() == 1
    assert page.locator("th", has_text="sampling, worst case").count() == 1  # each size's sampling bound
    css = page.evaluate("getComputedStyle(document.querySelector('header.page')).backgroundColor")
    assert css == "rgb(29, 39, 51)"  # the shared stylesheet (--ink), as on the replay and fleet pages
    page.screenshot(path=str(tmp_path / "diagnose.png"), full_page=True)
    assert (tmp_path / "diagnose.png").stat().st_size > 50_000

"""Self-checks of the third validation world (its own physics and file layout, not the project's)."""

from __future__ import annotations

import ast
import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from ebm_wear_monitor.validation.third import bag as bagmod
from ebm_wear_monitor.validation.third.cases import default_cases
from ebm_wear_monitor.validation.third.controller import CascadeForcePI
from ebm_wear_monitor.validation.third.generate import write_case
from ebm_wear_monitor.validation.third.plant import Actuator, load_nominal

PKG = Path(__file__).resolve().parents[2] / "ebm_wear_monitor" / "validation" / "third"
NOM = load_nominal()


def _apply_once(F_d: float = 20e3, hold: float = 0.3):
    """One nominal application under the cascade ECU; energy terms accumulated per step."""
    n = NOM
    p = Actuator(n, h=2.5e-4)
    c = CascadeForcePI(n, 1e-3, 48.0, 7.0, {})
    c.start_apply(F_d)
    E = dict.fromkeys(("el", "R", "emf", "motor", "fric"), 0.0)
    u, t_hold, k = 0.0, None, 0
    while p.t < 2.0 and (t_hold is None or p.t < t_hold + hold):
        if k % 4 == 0:
            u = c.update(p.th, p.w, p.force, p.i)
            if c.reached and t_hold is None:
                t_hold = p.t
        i0, w0 = p.i, p.w
        F = p.force
        Tc, _, B = p.friction(w0, F, n.c_x * F, p.t)
        p.step(u)
        ib = 0.5 * (i0 + p.i)
        E["el"] += u * ib * p.h
        E["R"] += n.R * 0.5 * (i0**2 + p.i**2) * p.h
        E["emf"] += n.K_E * w0 * ib * p.h
        E["motor"] += n.K_T * p.i * p.w * p.h
        if p.w:
            E["fric"] += (math.copysign(Tc, p.w) + B * p.w) * p.w * p.h
        k += 1
    d = p.x - n.x_ag
    E["L"] = 0.5 * n.L * p.i**2
    E["kin"] = 0.5 * n.J_me * p.w**2
    E["spring"] = 0.5 * n.K_b * d**2 if d > 0 else 0.0
    return p, E


def test_held_clamp_force_is_linear_law():
    p, _ = _apply_once()
    assert p.w == 0.0  # stuck at the held clamp
    assert p.force == pytest.approx(NOM.K_b * (p.x - NOM.x_ag), rel=1e-12)
    T_L = NOM.c_x * p.force
    assert abs(NOM.K_T * p.i - T_L) <= NOM.T_fs + NOM.G * p.force + 1e-9  # eq. 9 stick band


def test_energy_balance_closes():
    _, E = _apply_once()
    el = E["el"] - E["R"] - E["L"] - E["emf"]
    mech = E["motor"] - E["kin"] - E["spring"] - E["fric"]
    print(
        f"electrical residual {el / E['el']:.2e}, mechanical residual {mech / E['motor']:.2e}, "
        f"E_in {E['el']:.2f} J"
    )
    assert abs(el) < 0.01 * E["el"]
    assert abs(mech) < 0.01 * E["motor"]


@pytest.mark.parametrize("frac", [0.9, 1.1])
def test_stick_branch_holds_below_breakaway(frac):
    n = NOM
    p = Actuator(n, h=2.5e-4)
    F = 10e3
    p.th = (n.x_ag + F / n.K_b) / n.c_x
    T_s = n.T_fs + n.G * F
    i_ss = (n.c_x * F + frac * T_s) / n.K_T
    p.i = i_ss
    th0 = p.th
    for _ in range(800):  # 0.2 s at the steady current (stalled: u = R i)
        p.step(n.R * i_ss)
    moved = abs(p.th - th0)
    print(f"frac {frac}: moved {moved:.3e} rad")
    assert (moved == 0.0) if frac < 1 else (moved > 1e-3)


def test_cdr_matches_typestore():
    ts = bagmod.typestore()
    M = ts.types[bagmod.MSGTYPE]
    H, T = ts.types["std_msgs/msg/Header"], ts.types["builtin_interfaces/msg/Time"]
    for fid in ("", "a", "embu_link", "vehicle9_bogie2_embu3_load_cell"):
        m = M(header=H(stamp=T(sec=1709985700, nanosec=123456789), frame_id=fid), data=-1.25)
        assert bytes(ts.serialize_cdr(m, bagmod.MSGTYPE)) == bagmod.cdr(1709985700, 123456789, fid, -1.25)


def test_healthy_recording_layout(tmp_path):
    from rosbags.rosbag2 import Reader

    case = default_cases(NOM)[0]
    case = dataclasses.replace(case, schedule=case.schedule[:3])
    write_case(case, tmp_path, NOM)
    truth = json.loads((tmp_path / case.case_id / "truth.json").read_text())
    assert truth["kind"] == "none" and truth["effect"] is None
    ts = bagmod.typestore()
    got: dict[str, list] = {}
    with Reader(tmp_path / case.case_id / "bag") as r:
        for con, t_log, raw in r.messages():
            assert con.msgtype == bagmod.MSGTYPE
            m = ts.deserialize_cdr(raw, con.msgtype)
            st = m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec
            assert m.header.frame_id
            assert 0 <= t_log * 1e-9 - st <= 1.001e-3
            got.setdefault(con.topic, []).append((st, m.data))
    ns = case.namespace
    key_of = {f"{ns}/{v}": k for k, v in bagmod.TOPICS.items()}
    assert set(got) == set(key_of)
    F_max = max(a["F_d"] for a in case.schedule)
    for topic, rows in got.items():
        a = np.array(rows)
        rate = 1.0 / np.median(np.diff(np.sort(a[:, 0])))
        assert rate == pytest.approx(case.rates[key_of[topic]], rel=0.02)
        v = a[:, 1]
        if key_of[topic] == "force":  # N, compressive positive
            assert 0.9 * F_max < v.max() < 1.15 * F_max and v.min() > -400
        elif key_of[topic] == "angle":  # rad of the screw: a clamp is ~1 rad of travel
            assert 0.3 < np.ptp(v) < 3.0
        elif key_of[topic] == "velocity":  # rad/s of the screw
            assert 2.0 < np.abs(v).max() < 15.0
        else:  # A
            assert 1.0 < np.abs(v).max() <= case.ctrl["i_lim"] + 1.5


def test_no_project_imports():
    for f in PKG.glob("*.py"):
        for node in ast.walk(ast.parse(f.read_text())):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [] if node.level else [node.module or ""]
            else:
                continue
            bad = [n for n in names if n.split(".")[0] == "ebm_wear_monitor"]
            assert not bad, f"{f.name} imports {bad}"


def test_cases_deterministic():
    a, b = default_cases(NOM, 5), default_cases(NOM, 5)
    assert [dataclasses.asdict(x) for x in a] == [dataclasses.asdict(x) for x in b]
    assert len(a) == 36 and sum(c.kind == "none" for c in a) == 12

"""Effects of the foreign world: each form changes its named quantity by the stated amount, the
bags carry it, and the case sets have the composition brief A asks for."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from ebm_wear_monitor.validation.foreign import Case, case_set, write_case
from ebm_wear_monitor.validation.foreign.effects import (
    CATALOG,
    F_REF,
    FORMS,
    OUTSIDE,
    W_REF,
    Context,
    build,
)
from ebm_wear_monitor.validation.foreign.unit import load_actuator

from .foreign_read import read_bag

ACT = load_actuator()
N = 20


def _ctx(seed: int = 0) -> Context:
    onset = np.linspace(0.5, 40.0, N)
    return Context(act=ACT, onset=onset, duration=42.0, rng=np.random.default_rng(seed))


def _levels(phys, F: float, w: float) -> tuple[np.ndarray, np.ndarray]:
    """Extra kinetic and static friction levels of the hooks at one operating point."""
    Fa, wa, th = np.full(N, F), np.full(N, w), np.zeros(N)
    k = sum((f(Fa, wa, th) for f in phys.kinetic_extra), np.zeros(N))
    s = sum((f(Fa, th) for f in phys.static_extra), np.zeros(N))
    return np.broadcast_to(k, (N,)), np.broadcast_to(s, (N,))


@pytest.mark.parametrize(("name", "form"), [(n, f) for n in FORMS for f in FORMS[n]])
def test_every_form_changes_its_quantity_by_the_stated_relative_amount(name: str, form: str) -> None:
    s = 0.3
    phys, (rec,) = build(((name, form, s),), _ctx())
    a = ACT
    assert rec["name"] == name and rec["form"] == form and rec["catalog"] == (name in CATALOG)
    assert rec["equation"] and rec["quantity"]
    friction_ref = a.T_fc + a.G * F_REF
    if name == "viscous_friction":
        k, _ = _levels(phys, 0.0, W_REF)
        assert k == pytest.approx(s * a.B * W_REF)
        assert _levels(phys, 0.0, 2 * W_REF)[0][0] != pytest.approx(2 * s * a.B * W_REF)  # not linear
    elif name == "load_friction":
        k, st = _levels(phys, F_REF, 5.0)
        assert np.mean(k) == pytest.approx(s * a.G * F_REF, rel=0.35 if form == "coaxiality" else 1e-9)
        assert np.mean(st) == pytest.approx(np.mean(k))
    elif name == "efficiency_variation":
        w = 0.0 if form == "lowspeed_load" else W_REF
        assert _levels(phys, F_REF, w)[0] == pytest.approx(s * friction_ref)
    elif name == "preload_change":
        F = 0.0
        k, st = _levels(phys, F, 5.0)
        assert k == pytest.approx(s * a.T_fc)
        assert np.all(a.T_fs + st >= a.T_fc + k - 1e-12)  # breakaway never below sliding
    elif name == "stribeck":
        k, st = _levels(phys, 0.0, 0.0)
        assert k == pytest.approx(s * a.T_fc)
        assert _levels(phys, 0.0, 100.0)[0][0] < 0.05 * s * a.T_fc
        assert np.all(a.T_fs + st >= a.T_fc + k - 1e-12)
    elif name == "stiffness_nonlinearity":
        d28 = 28e3 / a.K_b
        assert phys.clamp(np.array([d28]), a.K_b)[0] == pytest.approx((1 + s) * 28e3)
    elif name == "clearance_growth":
        assert np.mean(phys.clearance_extra) == pytest.approx(rec["relative_change"] * a.x_ag)
        assert rec["relative_change"] == pytest.approx(s, rel=0.15)
        assert np.ptp(phys.clearance_extra) > 0  # varies per application
    elif name == "force_sensor_bias":
        measured = phys.cell(np.full(N, F_REF))
        assert np.mean(measured) / F_REF - 1 == pytest.approx(s, abs=0.01)
    elif name == "torque_constant_loss":
        assert phys.kt_factor == pytest.approx(1 - s)
    elif name == "backlash":
        assert phys.backlash * a.r_g == pytest.approx(s * a.x_ag)
    elif name == "torque_ripple":
        th = np.linspace(0, 2 * np.pi * a.i_g, 20001)
        ripple = phys.drive_extra[0](th)
        assert np.max(np.abs(ripple)) == pytest.approx(s * a.T_fc, rel=1e-3)
    else:  # friction drift: the factor on eq. 9 friction at the end of the recording
        k, _ = _levels(phys, 0.0, 5.0)
        assert k[-1] / a.T_fc == pytest.approx(rec["relative_change"], rel=1e-9)
        assert abs(k[-1]) > abs(k[0])


def test_case_sets_have_the_composition_of_the_brief() -> None:
    full = case_set("full")
    kinds = Counter(c.kind for c in full)
    assert kinds["none"] >= 30 and kinds["pair"] >= 8 and kinds["outside"] >= 8
    single = [c for c in full if c.kind == "effect"]
    per_form = Counter((c.forms[0][0], c.forms[0][1]) for c in single if not c.case_id.endswith("small"))
    for name in CATALOG:
        for form in FORMS[name]:
            assert per_form[name, form] >= 2, (name, form)
    for c in single:
        mag = abs(c.forms[0][2])
        assert (0.05 <= mag <= 0.10) if c.case_id.endswith("small") else mag >= 0.10
    outside = Counter(c.forms[0][0] for c in full if c.kind == "outside")
    assert set(outside) == set(OUTSIDE) and min(outside.values()) >= 2
    assert all(not c.effects for c in full if c.kind in ("none", "outside"))
    assert all(len(set(c.effects)) == 2 for c in full if c.kind == "pair")
    for c in full:  # the controller variants all appear with effects
        assert c.option("controller") in ("cascade", "position", "voltage")
    quick = case_set("quick")
    assert 20 <= len(quick) <= 25
    assert {c.forms[0][0] for c in quick if c.kind == "effect"} == set(CATALOG)


# --- the bags carry the effects: re-measured from recorded force and angle during holds ------
LAWS = (("clearance_growth", "ramp", 0.3), ("stiffness_nonlinearity", "power", 0.25),
        ("force_sensor_bias", "gain_offset_quadratic", -0.15), ("backlash", "play", 0.2))


@pytest.fixture(scope="module")
def law_bags(tmp_path_factory: pytest.TempPathFactory) -> dict:
    out = tmp_path_factory.mktemp("effects")
    cases = {name: Case(f"law.{name}", "effect" if name in CATALOG else "outside", 77 + k,
                        effects=(name,) if name in CATALOG else (), forms=((name, form, s),),
                        fixed=(("controller", "cascade"),))
             for k, (name, form, s) in enumerate(LAWS)}
    return {name: read_bag(write_case(c, out)) for name, c in cases.items()}


def _hold_samples(data: dict, truth: dict) -> tuple[dict, list[tuple[np.ndarray, np.ndarray]]]:
    """Per application: (recorded force - tare, nut travel from rest) during the last 50 ms of hold."""
    (ns, unit), = truth["units"].items()
    f = unit["foreign"]
    ang, frc = data[f"{ns}/screw/angle"], data[f"{ns}/axial_force"]
    rest = np.array(f["rest_angle_sensor_rad"])
    out = []
    for k, cmd in enumerate(f["applications"]["release_stamp_s"]):
        m = (frc["stamp"] > cmd - 0.05) & (frc["stamp"] < cmd)
        a = np.interp(frc["stamp"][m], ang["stamp"], ang["value"])
        out.append((frc["value"][m] - f["force"]["tare_N"], (a - rest[k]) * ACT.lead / (2 * np.pi)))
    return unit, out


def test_recorded_holds_follow_each_effects_declared_law(law_bags: dict) -> None:
    """The sidecar alone (equation parameters, clearance per application) predicts the recorded
    hold force from the recorded angle: a scorer needs nothing else."""
    for name, (data, truth) in law_bags.items():
        unit, holds = _hold_samples(data, truth)
        f = unit["foreign"]
        (rec,) = f["effects_detail"]
        p = rec["params"]
        tol_F = 4 * f["force"]["noise_std_N"] + f["force"]["lsb_N"] + 60.0
        for k, (F_meas, x) in enumerate(holds):
            d = x - unit["clearance_m"][k]
            if name == "stiffness_nonlinearity":
                F_true = ACT.K_b * p["d_5"] * (np.maximum(d, 0) / p["d_5"]) ** p["p"]
            elif name == "backlash" and f["encoder"]["side"] == "motor":
                F_true = ACT.K_b * (d - p["b_axial_m"])  # the motor turns through the play first
            else:
                F_true = ACT.K_b * d
            if name == "force_sensor_bias":
                F_true = (1 + p["g"]) * F_true + p["b"] + p["c"] * F_true**2 / 50e3
            assert np.median(F_meas - F_true) == pytest.approx(0.0, abs=tol_F), (name, k)
        if name == "clearance_growth":
            assert np.ptp(unit["clearance_m"]) > 30e-6  # the ramp shows in the truth
            assert unit["effects"]["clearance_growth"]["relative_change"] == pytest.approx(0.3)
        if name == "backlash":
            assert unit["effects"] == {} and f["kind"] == "outside"

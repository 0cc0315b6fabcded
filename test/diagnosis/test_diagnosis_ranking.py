"""Fits recover the parameters they were given; the verdict, the floors and the split behave as documented.

Data: closed-form brake cycles (diag_synth) obeying 004 eq. 1-9 with a known augmentation,
so each catalog effect must find its own parameters (an invariant, not a copied number).
"""

import dataclasses
import re
import types

import numpy as np
import pytest
from scipy import stats

from ebm_wear_monitor.diagnosis import tolerance
from ebm_wear_monitor.diagnosis.catalog import build_catalog, friction_refit
from ebm_wear_monitor.diagnosis.heldout import (
    MATERIAL_Z,
    direction_p,
    improvement_p,
    improvement_u,
    mean_above_zero,
)
from ebm_wear_monitor.diagnosis.pipeline import residual_model, summary
from ebm_wear_monitor.diagnosis.ranking import Model, Scorer, effect_fit, rank
from ebm_wear_monitor.diagnosis.ranking.criteria import DRIFT_ALPHA, trend_p
from ebm_wear_monitor.diagnosis.ranking.effect_fit import (
    against_tolerance_p,
    base_without_own,
    evaluate,
    nominal_sse,
    sampling_bound,
    sampling_caution,
    size_gradient,
)
from ebm_wear_monitor.diagnosis.ranking.scorer import Fit, fit, split_by_cycle
from ebm_wear_monitor.diagnosis.report import effect_note
from ebm_wear_monitor.diagnosis.residuals import Augment
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.twin.dynamics import actuator_model

from diag_synth import synth
from foreign_case import foreign_diagnosis

NOM = actuator_model(load_unit())

#: effect -> (augmentation in the data, the parameters the fit must return)
TRUTH = {
    "viscous_friction": (Augment(dB=1.5e-3), [1.5e-3]),
    "load_friction": (Augment(dG=1.0e-5), [1.0e-5]),
    "efficiency_variation": (Augment(eff_base=0.05, eff_speed=1e-3), [0.05, 1e-3]),
    "preload_change": (Augment(dT_fs=-0.08, dT_fc=-0.08), [-0.08]),
    "stribeck": (Augment(stribeck_torque=0.15, stribeck_speed=20.0), [0.15, 20.0]),
    "stiffness_nonlinearity": (Augment(stiffness_quad=2e10), [2e10]),
    "clearance_growth": (Augment(clearance=3e-5), [3e-5]),
    "force_sensor_bias": (Augment(force_gain=0.06), [0.06]),
}


def scorer(aug, seed=0, cycles=10, **kw):
    rec = synth(NOM, aug, cycles=cycles, seed=seed, **kw)
    model = residual_model(rec, NOM)
    sensors = Scorer.sensors(model)
    return sensors.scaled(sensors.noise_scale()), model


def catalog(model):
    return build_catalog(NOM, float(model.speed.max()), float(model.force.max()))


@pytest.mark.parametrize("name", list(TRUTH))
def test_each_effect_recovers_its_own_parameters(name):
    aug, expected = TRUTH[name]
    sc, model = scorer(aug, force_offset=180.0)  # a tare in the data too
    f = fit(sc, catalog(model)[name], sc.base)
    for value, err, true in zip(f.theta, f.stderr, expected, strict=True):
        # within 4 cluster-robust standard errors or 5 % (the fit's resolution on 5 calibration cycles)
        assert abs(value - true) <= max(4.0 * err, 0.05 * abs(true)), (name, value, err, true)


@pytest.mark.parametrize("name", ["load_friction", "clearance_growth", "force_sensor_bias",
                                  "stiffness_nonlinearity"])
def test_strong_effect_is_named(name):
    aug, _ = TRUTH[name]
    sc, model = scorer(aug, seed=3, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect" and r.effect.effect.name == name
    assert r.joint.gap_after < 0.5 * r.gap_before
    # only a clearance growth has a known look-alike outside the catalog (a play), and the summary says
    # what of it the recording showed: here the lost-motion test is made (two samples a window) and finds
    # the release's friction over the extra travel (test_diagnosis_play.py has the case where it is not)
    text = summary(r)
    assert ("crossed without the screw's friction" in text) == (name == "clearance_growth"), text
    if name == "clearance_growth":
        assert r.play is not None and not r.play_decided
        assert text.endswith("read as a wider clearance."), text
    # the summary states what the verdict judged: the share of the material model error closed, >= 50 %
    assert "model error the twin within its tolerance leaves" in text, text
    for ch, w in r.unexplained_share.items():
        if w > tolerance.MATERIAL_SHARE[ch]:
            closed = 1.0 - r.joint.share[ch] / w
            assert f"{100.0 * closed:.0f} % of the {ch} model error" in text and closed >= 0.5
    immaterial = dataclasses.replace(r, unexplained_share=dict.fromkeys(r.unexplained_share, 0.0))
    assert "leaves no material model error" in summary(immaterial)


def test_summary_says_why_a_position_torque_decided():
    """The two sentences of an open-set verdict (ranking.open_set_verdict): the tolerant twin misses a
    material position torque; the selected effects close less than half of the explainable error."""
    from ebm_wear_monitor.diagnosis.openset import Periodic
    from ebm_wear_monitor.diagnosis.ranking import OpenSet

    sc, model = scorer(TRUTH["load_friction"][0], seed=3, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect"

    def said(share, on_effects=True):
        periodic = Periodic(2, 0.1 * np.sqrt(2), 0.1, 0.002, 0.04, 1e-9, 100.0, 50.0)
        o = OpenSet(periodic, on_effects, share, True)
        return summary(dataclasses.replace(r, verdict="unexplained", open_set=o))

    assert said(None, on_effects=False).startswith("The twin, even within its tolerance, misses")
    text = said(0.3)
    assert text.startswith("The best known effects (load friction) close only 30 % of the explainable")
    assert "100 ± 2 mN m RMS" in text


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_no_effect_gives_verdict_none(seed):
    sc, model = scorer(Augment(), seed=seed, cycles=12)
    assert rank(sc, catalog(model)).verdict == "none"


def test_deviation_within_the_budget_is_not_material():
    # every budget entry at 90 % of its bound at once: a healthy unit as far off as the budget allows
    dev = Augment()
    for t in tolerance.BUDGET:
        dev = tolerance.apply(dev, t.deviation(NOM, 0.0))
    scaled = Augment(**{f: 0.9 * getattr(dev, f) for f in ("dB", "clearance", "force_gain")})
    sc, model = scorer(scaled, seed=5, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "none", [(f.effect.name, f.size, f.floor) for f in r.fits[:3]]


@pytest.mark.parametrize(("gain", "material"), [(0.03, False), (0.07, True), (-0.07, True)])
def test_the_force_channels_materiality_is_the_gain_the_budget_leaves(gain, material):
    # a load-cell gain error g. In the force channel the budget makes gains of 0.97 x 0.99 to 1.03 x 1.01
    # (K_b +-3 %, the load cell +-1 %), so the twin within its tolerance leaves at most the excess e beyond
    # that range times the clamp force; the one other entry acting there, the clearance's +-5 um (these
    # parks have no band), is an offset and can take no more of e F than its mean, so at least
    # e std(F) / RMS(F) is left (both weighted as the share is, sigma^-4, over the held-out blocks in
    # contact). Closed-form bounds from the recording's forces; 3 % lies within the budget (e = 0), 7 %
    # beyond the channel's 1 % bound
    sc, _ = scorer(Augment(force_gain=gain), cycles=16)
    share = sc.unexplained_share(sc.base)["force"]
    high, low = 1.03 * 1.01, 0.97 * 0.99  # the gains the budget can make in the force channel
    excess = max(0.0, (1.0 + gain) / high - 1.0, 1.0 - (1.0 + gain) / low)
    b = sc.model.blocks
    rows = sc.valid(sc.split.heldout, "force") & (b.force > sc.model.seg.force_rise)
    F, w = b.force[rows], sc.sigma_force[rows] ** -4.0
    mean = np.average(F, weights=w)
    spread = np.sqrt(np.average((F - mean) ** 2, weights=w) / np.average(F * F, weights=w))
    assert excess * spread - 1e-3 <= share <= excess + 1e-3, (share, excess, spread)
    assert (share > tolerance.MATERIAL_SHARE["force"]) is material, (share, excess)


def test_two_effects_are_both_named():
    sc, model = scorer(Augment(clearance=4e-5, dG=1.2e-5), seed=6, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect"
    assert {f.effect.name for f in r.selected} == {"clearance_growth", "load_friction"}
    assert r.joint.shrink > 0.9


def test_effect_outside_the_catalog_is_unexplained():
    # a 15 % loss of the motor's torque constant: more current for every torque, in both directions
    sc, model = scorer(Augment(), seed=7, cycles=12, drive_gain=0.15)
    r = rank(sc, catalog(model))
    assert r.verdict == "unexplained", (r.top.effect.name, r.top.shrink, r.unexplained_share)
    # the summary states the model error the twin within its tolerance leaves, against its 2 % bound; the
    # tolerances can only take error away, so it lies between the bound and the whole loss, 0.15 / 0.85 of
    # the torque the twin predicts
    words = summary(r)
    left = re.search(r"leaves (\d+\.\d+) % of the motor torque beyond the noise where 2 % is material",
                     words)
    assert left is not None, words
    assert 2.0 < float(left.group(1)) <= 100 * 0.15 / 0.85
    assert "within the recording" not in words  # no friction drifts here: the drift words would mislead


def test_a_healthy_unit_whose_noise_the_sensors_understate_reads_none(tmp_path):
    # the blind draw full_j's one false positive (2 kHz, cascade ECU, 12-bit motor-side encoder): its
    # free-travel blocks scatter 11 times the noise propagated from the sensors and its force is held by a
    # creep of one count every 3-8 ms; with the propagated noise alone it read 2.7 % of the motor torque
    # beyond the noise against the 2 % bound: unexplained.  Not a blind test: the change was written from
    # this case; the draw full_k was run blind after it
    res = foreign_diagnosis("full_j", "none_j003", tmp_path)
    assert res.verdict == "none", res.summary


@pytest.mark.parametrize("seed", [1, 3])
def test_a_creep_the_encoder_does_not_resolve_is_no_effect(seed):
    # a healthy unit with a 12-bit encoder on the motor creeps on through the hold at 0.1 rad/s of the screw,
    # less than one count per sample, with a stick-slip friction averaging 3/4 of eq. 9's sliding branch:
    # the encoder cannot tell that creep from a steady one, so it is no effect and no position structure
    # (before the unresolved creep was counted, seeds 1 and 3 read an efficiency variation: these seeds
    # were chosen as the ones that failed; seeds 2, 4 and 5 hold no moving block in the hold)
    quantum = 2.0 * np.pi / (4096 * NOM.gear_ratio)
    rec = synth(NOM, Augment(), cycles=12, seed=seed, creep=0.1, creep_friction=0.75, angle_quantum=quantum,
                noise={"angle": 0.0, "velocity": 0.05, "axial_force": 30.0, "current": 0.03})
    model = residual_model(rec, NOM)
    b = model.blocks
    creep = b.moving & (b.phase == Phase.FORCE_MAINTENANCE)
    assert creep.sum() > 100
    # the friction the creep misses, a quarter of T_fc + G F, lies within the band the blocks carry
    missed = 0.25 * (NOM.friction.coulomb + NOM.friction.load_coefficient * b.force[creep])
    assert np.all(missed < 2.0 * model.ambiguous_torque[creep])
    sensors = Scorer.sensors(model)
    r = rank(sensors.scaled(sensors.noise_scale()), catalog(model))
    assert r.verdict == "none", ([f.effect.name for f in r.selected], r.open_set)


@pytest.mark.parametrize("seed", [8, 9, 13])
def test_friction_drifting_within_the_recording_is_unexplained(seed):
    # load friction growing from nothing to +57 % of G over the recording (outside the catalog): the load
    # friction fit is significant and material, but its size trends with time
    sc, model = scorer(Augment(), seed=seed, cycles=12, dG_drift=1.0e-5)
    r = rank(sc, catalog(model))
    load = next(f for f in r.fits if f.effect.name == "load_friction")
    assert load.drift is not None and load.drift.drifting, load.drift
    assert load.drift.late > load.drift.early and load.drift.p_value < DRIFT_ALPHA
    assert r.verdict == "unexplained", [f.effect.name for f in r.selected]
    # the summary says which friction drifts and how much: dG grows linearly over the 12 cycles, so the
    # late half's mean exceeds the early half's by 6/11 of dG_drift (mean cycle age 8.5/11 against 2.5/11)
    text = summary(r)
    halves = re.match(r"The fitted load friction changes within the recording: its magnitude is (\S+) % "
                      r"on the early half of the applications and (\S+) % on the late half "
                      r"\(late - early ± (\S+) %; fraction of G", text)
    assert halves is not None, text
    early, late, std = (float(v) / 100 for v in halves.groups())
    truth = 6 / 11 * 1.0e-5 / NOM.friction.load_coefficient
    assert abs(late - early - truth) < 3 * std + 1e-3, (early, late, std, truth)


@pytest.mark.parametrize(("seed", "dG"), [(8, 6e-6), (13, 4e-6)])
def test_a_material_friction_drift_is_unexplained_though_the_tolerance_absorbs_most(seed, dG):
    # a smaller drift (+34 % and +23 % of G by the last cycle): the twin within its tolerance leaves less
    # than the torque channel's materiality share, yet the load friction it takes is material and trends
    sc, model = scorer(Augment(), seed=seed, cycles=12, dG_drift=dG)
    r = rank(sc, catalog(model))
    assert r.unexplained_share["torque"] < tolerance.MATERIAL_SHARE["torque"]
    load = next(f for f in r.fits if f.effect.name == "load_friction")
    assert load.material and load.drift is not None and load.drift.drifting, load.drift
    assert r.verdict == "unexplained"


@pytest.mark.parametrize("seed", [8, 9])
def test_constant_friction_does_not_drift(seed):
    sc, model = scorer(TRUTH["load_friction"][0], seed=seed, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect" and r.effect.effect.name == "load_friction"
    assert r.effect.drift is not None and not r.effect.drift.drifting, r.effect.drift


def _trend_draws(rng, n=20, *, ordered=False, drift=0.0):
    """Sizes per cycle that depend on the cycle's demand (a catalog form that fits the real one only
    approximately) and, with ``drift``, on time; the stated variances are wrong: 4 to 400 times below
    the scatter, which is the same for every cycle (a form error, not noise)."""
    time = np.sort(rng.uniform(0.0, 60.0, n))
    force = rng.uniform(5e3, 28e3, n)
    if ordered:
        force = np.sort(force)  # demands rising through the recording
    sd = 0.01
    s = 0.1 + 0.03 * (force - 16e3) / 7e3 + drift * time / 60.0 + rng.normal(0.0, sd, n)
    return s, (sd / 2) ** 2 / np.exp(rng.uniform(0.0, np.log(100.0), n)), time, force[:, None]


def test_the_time_trend_test_holds_the_operating_mix():
    rng = np.random.default_rng(11)
    draws = 400
    # no drift, random demands: the test keeps its level although the stated variances are wrong and
    # unequal (a standard error scaled by the residual scatter alone gave 5-7 % here)
    null = [trend_p(*_trend_draws(rng)) for _ in range(draws)]
    assert np.mean(np.array(null) < DRIFT_ALPHA) <= 3 * DRIFT_ALPHA
    # no drift, demands rising with time: the size follows the demands, not time
    ordered = [_trend_draws(rng, ordered=True) for _ in range(draws)]
    assert np.mean([trend_p(*d) < DRIFT_ALPHA for d in ordered]) <= 3 * DRIFT_ALPHA
    # without the mix the same data would read as a drift
    assert np.mean([trend_p(s, v, t, np.zeros((t.size, 0))) < DRIFT_ALPHA for s, v, t, _ in ordered]) > 0.9
    # a drift of 0.1 over the recording (10 sd of the scatter) with random demands is found, in spite of
    # the wrong weights (a drift of 5 sd: in about 70 % of the draws)
    assert np.mean([trend_p(*_trend_draws(rng, drift=0.1)) < DRIFT_ALPHA for _ in range(draws)]) > 0.9


def test_split_alternates_and_needs_four_cycles():
    s = split_by_cycle(np.repeat(np.arange(6), 3))
    assert list(s.heldout_cycles) == [1, 3, 5]
    # demands with period 4 (8, 14, 20, 26 kN ...): both sides get every force level
    peak = np.repeat(np.resize([8e3, 14e3, 20e3, 26e3], 8), 3)
    s = split_by_cycle(np.repeat(np.arange(8), 3), peak)
    held_levels = {peak[3 * c] for c in s.heldout_cycles}
    assert held_levels == {8e3, 14e3, 20e3, 26e3}
    assert not np.any(s.calibration & s.heldout)
    with pytest.raises(InputError, match="at least 4"):
        split_by_cycle(np.repeat(np.arange(3), 3))


def test_the_one_sided_mean_test_is_students():
    # scipy's one-sample t test, written apart from it, and the sign rule where every contrast is equal
    d = np.random.default_rng(3).normal(0.4, 1.0, 9)
    mean, se, p = mean_above_zero(d)
    ref = stats.ttest_1samp(d, 0.0, alternative="greater")
    assert mean == pytest.approx(d.mean()) and se == pytest.approx(d.std(ddof=1) / 3.0)
    assert p == pytest.approx(ref.pvalue, rel=1e-9)
    assert mean_above_zero(np.full(5, 2.0))[2] == 0.0 and mean_above_zero(np.full(5, -2.0))[2] == 1.0


def test_improvement_p_is_conservative_without_effect_and_small_with_one():
    rng = np.random.default_rng(7)
    delta = 0.3 * np.sin(np.linspace(0, 20, 400))  # a fixed correction "fitted elsewhere"
    p_null = [improvement_p(z, z - delta) for z in rng.normal(size=(2000, 400))]
    # under "no effect" P(p < 0.05) must not exceed 0.05 (it is far below: the mean is negative)
    assert np.mean(np.array(p_null) < 0.05) <= 0.05
    noise = rng.normal(size=400)
    assert improvement_p(noise + 3.0 * delta, noise) < 1e-6


def test_direction_p_holds_its_level_and_doubles_the_separation():
    """Under "no effect" the direction test's p-value is uniform (its level is the nominal one, where the
    improvement test's falls far below it); with the effect present and fitted right, V = U + |delta| / 2
    (heldout.direction_p), so a correction the improvement test mostly misses the direction test mostly
    finds."""
    rng = np.random.default_rng(11)
    delta = 0.2687 * np.sin(np.linspace(0, 20, 400))  # |delta| = 3.8, a fixed correction "fitted elsewhere"
    p_v = np.array([direction_p(z, z - delta) for z in rng.normal(size=(4000, 400))])
    p_u = np.array([improvement_p(z, z - delta) for z in rng.normal(size=(4000, 400))])
    for level in (0.05, 0.2, 0.5):  # uniform: binomial sd of the rate at 4000 draws <= 0.008
        assert abs(np.mean(p_v < level) - level) < 4.0 * np.sqrt(level * (1.0 - level) / 4000)
    assert np.mean(p_u < 0.05) < 0.002  # N(-1.9, 1) against N(0, 1): about 2e-4
    present = [(direction_p(n + delta, n), improvement_p(n + delta, n)) for n in rng.normal(size=(2000, 400))]
    pv, pu = np.array(present).T
    # at nominal 0.05 / 8: V ~ N(3.8, 1) passes about 90 % of the time, U ~ N(1.9, 1) about 27 %
    assert np.mean(pv < 0.05 / 8) > 0.85 and np.mean(pu < 0.05 / 8) < 0.35


def test_the_cycles_scale_keeps_the_level_under_shared_cycle_error_at_little_cost_in_power():
    """Held-out rows of one cycle sharing model error along the correction (b_c ~ N(0, tau^2) per cycle,
    10 cycles of 40 rows): with independent rows' scale |delta| the direction test rejects "no effect" at
    many times its level; the cluster-robust scale (heldout._correction) brings it down to about 3 times
    (the normal reference over 10 cycles is still liberal, a known limit), and with independent noise it
    keeps most of the power of the independent-row test."""
    rng = np.random.default_rng(5)
    cycles = np.repeat(np.arange(10), 40)
    shape = np.tile(np.sin(np.linspace(0.0, 3.0, 40)), 10)
    delta = 4.0 * shape / np.linalg.norm(shape)  # |delta| = 4: V ~ N(4, 1) when present
    level, n = 0.05 / 8, 3000

    def rates(tau: float, present: bool) -> tuple[float, float]:
        hits = np.zeros(2)
        for _ in range(n):
            e = rng.normal(size=400) + tau * rng.normal(size=10)[cycles] * shape
            zb, za = (e + delta, e) if present else (e, e - delta)
            hits += (direction_p(zb, za) < level, direction_p(zb, za, cycles) < level)
        return hits[0] / n, hits[1] / n

    iid, clustered = rates(0.6, present=False)
    assert iid > 15 * level and clustered < 4 * level  # about 30 and 3 times the level
    iid, clustered = rates(0.0, present=False)
    assert clustered <= iid + 3 * np.sqrt(level / n)  # the floor: never above the independent-row test
    iid, clustered = rates(0.0, present=True)
    assert iid > 0.88 and clustered > 0.9 * iid  # N(4, 1) at 2.5: 93 %; the cycles' scale about 89 %
    # V - U = |delta|^2 / (2 scale) with the floor binding (scale = |delta| = 4) and not (a shared error)
    scales = []
    for za in (np.zeros(400), rng.normal(size=400) + 2.0 * rng.normal(size=10)[cycles] * shape):
        scales.append(max(4.0, np.sqrt(np.sum(np.bincount(cycles, weights=za * delta) ** 2))))
        u, v = improvement_u(za + delta, za, cycles), stats.norm.isf(direction_p(za + delta, za, cycles))
        assert v - u == pytest.approx(8.0 / scales[-1], rel=1e-9)
        assert u == pytest.approx(improvement_u(za + delta, za) * 4.0 / scales[-1], rel=1e-9)
    assert scales[0] == 4.0 and scales[1] > 6.0  # the floor, then the cycles' scale
    # the floor: residual exactly along delta with nothing after it is V = |delta| with or without cycles
    assert direction_p(delta, 0.0 * delta, cycles) == direction_p(delta, 0.0 * delta) == stats.norm.sf(4.0)
    # only which rows share a cycle counts, not the labels
    za = rng.normal(size=400) + rng.normal(size=10)[cycles] * shape
    assert direction_p(za + delta, za, 7 * cycles + 3) == direction_p(za + delta, za, cycles)
    named = np.array([f"c{c}" for c in cycles])
    assert direction_p(za + delta, za, named) == direction_p(za + delta, za, cycles)
    with pytest.raises(ValueError, match="cycle labels"):
        direction_p(za + delta, za, cycles[1:])


def test_nested_extension_keeps_the_first_effect_and_recovers_the_second():
    """A force-channel effect (stiffness) and a torque-channel one (viscous): the second fitted on top of
    the first returns the first's parameters unchanged and its own within its resolution."""
    from ebm_wear_monitor.diagnosis.ranking import evaluate, nominal_sse
    from ebm_wear_monitor.diagnosis.ranking.effect_fit import extend

    viscous = 3e-3  # [N m s/rad]
    sc, model = scorer(Augment(stiffness_quad=2e10, dB=viscous), seed=4, cycles=12)
    cat = catalog(model)
    s_before = nominal_sse(sc)
    gap = sc.gap(sc.base)
    first = evaluate(sc, cat["stiffness_nonlinearity"], s_before, gap)
    pair = extend(sc, first, cat["viscous_friction"], s_before, gap)
    assert pair.effect.name == "stiffness_nonlinearity+viscous_friction"
    # the first effect's correction and its channel's (force) nuisances are those of its own fit
    assert pair.model.aug.stiffness_quad == first.model.aug.stiffness_quad
    assert pair.model.aug.force_skew == first.model.aug.force_skew
    assert pair.model.aug.force_lag == first.model.aug.force_lag
    value, err = pair.theta[1], pair.stderr[1]
    assert abs(value - viscous) <= max(4.0 * err, 0.05 * viscous), (value, err)
    # the second effect's test of the forward selection: held out, at 0.05 over the 7 other effects
    assert pair.score > first.score and improvement_p(first.z_heldout, pair.z_heldout) < 0.05 / 7


@pytest.mark.xfail(strict=False, reason=(
    "machine-dependent since 687984d: a phase's lag-2 noise estimate needs 12 differences "
    "(ranking.blocknoise.QUIET_DIFFS), a count at its edge for this closed-form pair; where the torque "
    "noise scale comes out larger the viscous addition misses its test (the fresh-clone CI machine of "
    "c25210c: xfailed), elsewhere it passes (the machine of be722b5, at c25210c and after: p = 0.0031 "
    "against 0.05 / 7)"))
def test_effects_in_different_channels_are_both_named():
    from ebm_wear_monitor.diagnosis.ranking.effect_fit import without_own

    sc, model = scorer(Augment(stiffness_quad=2e10, dB=1.5e-3), seed=8, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect"
    assert [f.effect.name for f in r.selected] == ["stiffness_nonlinearity", "viscous_friction"]
    # test (a) of the addition: held out, against the first effect and against it refitted with the
    # viscous budget entry at zero, the larger p-value (each test written out here)
    assert r.joint is not None
    first = next(f for f in r.fits if f.effect.name == "stiffness_nonlinearity")
    nested = sc.z(without_own(sc, first, r.selected[1].effect), sc.split.heldout)
    p = max(improvement_p(first.z_heldout, r.joint.z_heldout), improvement_p(nested, r.joint.z_heldout))
    assert r.joint.p_value == pytest.approx(p, rel=1e-9) and p < 0.05 / 7


def test_a_change_that_makes_a_channel_materially_wrong_is_not_supported():
    """Test (e): the error a change adds in a channel is the quadrature difference of the held-out
    shares, judged against that channel's materiality share (2 % of the torque, 1 % of the force)."""
    from ebm_wear_monitor.diagnosis.ranking.criteria import worsens

    # a force-sensor gain that closed the force gap of a foreign stiffness + Stribeck recording by putting
    # 14 % of the motor torque into the torque residual (the quick foreign set, before test (e))
    assert worsens({"torque": 0.0117, "force": 0.0202}, {"torque": 0.1405, "force": 0.0098})
    # 3.0 % -> 3.5 %: adds sqrt(3.5^2 - 3.0^2) = 1.8 % of the torque, below 2 %
    assert not worsens({"torque": 0.030, "force": 0.02}, {"torque": 0.035, "force": 0.0})
    # 0.5 % -> 1.2 % of the force: adds 1.09 %, above 1 %
    assert worsens({"torque": 0.0, "force": 0.005}, {"torque": 0.0, "force": 0.012})


def test_test_e_guards_the_first_effect_and_every_addition(monkeypatch):
    """Test (e) is asked for the first effect (against the twin within its tolerance) and for the second
    (against the first); when it fails, nothing is selected."""
    from ebm_wear_monitor.diagnosis.ranking import criteria, selection

    sc, model = scorer(Augment(clearance=4e-5, dG=1.2e-5), seed=6, cycles=12)
    asked = []
    real = criteria.worsens

    def spy(before, after):
        asked.append(dict(before))
        return real(before, after)

    for module in (criteria, selection):  # the first effect's test and every addition's
        monkeypatch.setattr(module, "worsens", spy)
    r = rank(sc, catalog(model))
    assert len(r.selected) == 2
    assert r.unexplained_share in asked  # the first effect, against W
    first = next(f for f in r.fits if f.effect.name == r.selected[0].effect.name)
    assert first.share in asked  # the addition, against the first
    for module in (criteria, selection):
        monkeypatch.setattr(module, "worsens", lambda before, after: True)
    assert rank(sc, catalog(model)).selected == []


@pytest.mark.parametrize(("aug", "seed"), [
    (Augment(dG=1.2e-5, stribeck_torque=0.15, stribeck_speed=20.0), 2),
    (Augment(dG=0.8e-5, stribeck_torque=0.2, stribeck_speed=30.0), 1)])
def test_the_first_effect_is_chosen_again_given_the_second(aug, seed, monkeypatch):
    """Load friction and a Stribeck fall together.  Alone, an efficiency varying with speed (it nests load
    friction) or a preload change takes part of both and is selected first; greedy selection keeps it
    (efficiency + Stribeck, preload + load friction + Stribeck), the floating step chooses the first
    again given the second."""
    from ebm_wear_monitor.diagnosis.ranking import selection

    sc, model = scorer(aug, seed=seed, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect"
    assert {f.effect.name for f in r.selected} == {"load_friction", "stribeck"}
    load = next(f for f in r.selected if f.effect.name == "load_friction")
    true = aug.dG / NOM.friction.load_coefficient
    assert abs(load.size - true) <= max(4.0 * load.size_std, 0.1 * true), (load.size, load.size_std, true)
    # the same data without the floating step: the greedy first choice stays
    monkeypatch.setattr(selection, "_rechoose_first",
                        lambda sc, fits, current, selected, **kw: (current, selected))
    greedy = rank(sc, catalog(model))
    assert {f.effect.name for f in greedy.selected} != {"load_friction", "stribeck"}


def test_a_force_channel_effect_fits_the_nuisances_that_time_the_load_torque_on_the_torque_rows_too():
    """The force reading's skew and lag time the load torque too (004 eq. 1): a force-channel effect refits
    them on every row they move, torque rows included, so its fit cannot buy a force fit with an unseen
    torque error (test (e) against the twin within its tolerance holds)."""
    from ebm_wear_monitor.diagnosis.ranking import evaluate, nominal_sse
    from ebm_wear_monitor.diagnosis.ranking.criteria import worsens
    from ebm_wear_monitor.diagnosis.residuals import CHANNELS

    sc, model = scorer(Augment(clearance=3e-5), seed=3)
    clearance = catalog(model)["clearance_growth"]
    f = fit(sc, clearance, sc.base)
    assert f.theta[0] == pytest.approx(3e-5, rel=0.1)
    assert f.z.size == sc.rows(sc.split.calibration, CHANNELS).size  # torque and force rows
    assert f.z.size > fit(sc, clearance, sc.base, search=True).z.size  # a search: its own rows only
    ef = evaluate(sc, clearance, nominal_sse(sc), sc.gap(sc.base))
    assert not worsens(sc.unexplained_share(sc.base), ef.share)
    assert ef.share["torque"] <= sc.unexplained_share(sc.base)["torque"] + 1e-3


def test_an_addition_is_tested_against_the_model_with_its_own_budget_entries_held_at_zero():
    """The second effect's test is nested like the first's: against the selected model refitted with the
    added effect's own budget entries at zero, not against a model whose tolerances already mimic it."""
    from ebm_wear_monitor.diagnosis.ranking import evaluate, nominal_sse
    from ebm_wear_monitor.diagnosis.ranking.effect_fit import without_own

    sc, model = scorer(Augment(stiffness_quad=2e10, dB=1.5e-3), seed=8, cycles=12)
    cat = catalog(model)
    first = evaluate(sc, cat["stiffness_nonlinearity"], nominal_sse(sc), sc.gap(sc.base))
    null = without_own(sc, first, cat["viscous_friction"])
    viscous = [t.name for t in tolerance.BUDGET].index("viscous")
    assert null.t[viscous] == 0.0 and first.model.t[viscous] != 0.0
    assert null.aug.stiffness_quad == pytest.approx(first.model.aug.stiffness_quad, rel=0.05)
    assert without_own(sc, first, cat["stribeck"]) is first.model  # no budget entry of its own


@pytest.mark.parametrize("seed", [5, 6])
def test_the_best_pair_fits_two_effects_together(seed):
    """Best subset of size two (``best_pair``): a clearance growth and a force-sensor gain, fitted
    together from the twin within its tolerance, return both their parameters; on a healthy recording
    no pair passes."""
    from ebm_wear_monitor.diagnosis.ranking import nominal_sse, ranked_fits
    from ebm_wear_monitor.diagnosis.ranking.selection import best_pair

    sc, model = scorer(Augment(clearance=3e-5, force_gain=0.06), seed=seed, cycles=12)
    fits = ranked_fits(sc, catalog(model))
    found = best_pair(sc, fits, nominal_sse(sc), sc.gap(sc.base), w_share=sc.unexplained_share(sc.base),
                      closes=lambda f: True)
    assert found is not None
    pair, parts = found
    assert pair.effect.name in ("clearance_growth+force_sensor_bias", "force_sensor_bias+clearance_growth")
    assert {f.effect.name for f in parts} == {"clearance_growth", "force_sensor_bias"}
    truth = {"clearance_growth": 3e-5, "force_sensor_bias": 0.06}
    for f in parts:
        true = truth[f.effect.name]
        assert abs(f.theta[0] - true) <= max(4.0 * f.stderr[0], 0.05 * true), (f.effect.name, f.theta)
    healthy, hmodel = scorer(None, seed=seed, cycles=12)
    hfits = ranked_fits(healthy, catalog(hmodel))
    assert best_pair(healthy, hfits, nominal_sse(healthy), healthy.gap(healthy.base),
                     w_share=healthy.unexplained_share(healthy.base), closes=lambda f: True) is None


def test_rank_takes_the_best_pair_where_greedy_selection_leaves_the_material_error_open(monkeypatch):
    """The route in ``rank``: with the greedy selection made to find nothing, a clearance growth and a
    force-sensor gain are still named, both, by the best pair of two; where the twin within its tolerance
    leaves no material error (a healthy recording) the pair search is not made and the verdict is none."""
    from ebm_wear_monitor.diagnosis.ranking import verdict

    def greedy_finds_nothing(sc, fits, level, s_before, gap_before, *, w_share):
        return [], None, list(fits)

    monkeypatch.setattr(verdict, "forward_select", greedy_finds_nothing)
    sc, model = scorer(Augment(clearance=3e-5, force_gain=0.06), seed=5, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect"
    assert {f.effect.name for f in r.selected} == {"clearance_growth", "force_sensor_bias"}
    assert r.joint is not None and r.joint.effect.name.count("+") == 1
    searched = []
    monkeypatch.setattr(verdict, "best_pair", lambda *a, **kw: searched.append(1))
    healthy, hmodel = scorer(None, seed=5, cycles=12)
    assert rank(healthy, catalog(hmodel)).verdict == "none" and not searched


def test_an_effect_that_does_not_shrink_the_held_out_gap_is_not_named(monkeypatch):
    """Test (c)'s second half, in ``rank``: the selection's model as fitted, but with its held-out gap
    made no smaller than the nominal twin's (shrink 0), names nothing. The verdict then follows the
    rules without a selection: here a candidate closes the material error by half, so not
    ``unexplained`` for want of an effect."""
    from ebm_wear_monitor.diagnosis.ranking import verdict

    real = verdict.forward_select

    def gap_unchanged(*args, **kw):
        selected, joint, candidates = real(*args, **kw)
        if joint is not None:
            joint = dataclasses.replace(joint, shrink=0.0)
        return selected, joint, candidates

    sc, model = scorer(TRUTH["load_friction"][0], seed=3, cycles=12)
    assert rank(sc, catalog(model)).verdict == "effect"
    monkeypatch.setattr(verdict, "forward_select", gap_unchanged)
    r = rank(sc, catalog(model))
    assert r.selected == [] and r.joint is None
    assert not any(f.drifting for f in r.fits) and r.verdict == "none"


def test_a_foreign_healthy_unit_whose_viscous_change_was_below_the_twins_is_none(tmp_path):
    """The case that prompted (c)'s second half, from the independently written foreign generator: a
    healthy unit recorded at 200 Hz (``full_g`` none_g003), on which a viscous change was significant
    against the twin within its tolerance and material (38 % +- 7 % of B), yet left the held-out gap no
    smaller than the nominal twin's. The change was a drag *below* the twin's: with the catalog's viscous
    friction one-sided (a drag larger than modelled, interface.md) its fit stops at zero and the unit
    reads ``none`` before (c) is asked; the rule itself is tested on closed-form data above. Not a blind
    test; the other healthy foreign units and every effect verdict of the foreign draws are the wider
    check (README)."""
    res = foreign_diagnosis("full_g", "none_g003", tmp_path)
    assert res.verdict == "none" and res.effects == []
    viscous = next(e for e in res.ranking if e.effect == "viscous_friction")
    assert viscous.at_limit and viscous.parameters["dB"].value == pytest.approx(0.0, abs=1e-6)


def test_a_foreign_viscous_drag_too_weak_to_name_is_the_nearest_effect_of_the_summary(tmp_path):
    """A viscous drag of +113 % of B from the independently written foreign generator (``full_e``
    viscous_friction.power.0) that the held-out test does not confirm once eight effects are tried (the
    twin within its tolerance absorbs most of it, README "Where the misses are") reads ``none``; the
    summary still tells the user which effect came nearest, with its size above its floor and why it was
    not named."""
    res = foreign_diagnosis("full_e", "viscous_friction.power.0", tmp_path)
    assert res.verdict == "none"
    assert "Nearest, not named: lubricant viscous drag" in res.summary
    assert "not significant once" in res.summary
    viscous = next(e for e in res.ranking if e.effect == "viscous_friction")
    assert viscous.material and 0.05 / len(res.ranking) <= viscous.p_value < 0.05


def test_the_fit_stops_at_the_limits_and_an_effect_on_its_limit_is_not_named():
    """Data whose viscous drag is B - 2 B (a negative B, no real drive has it): the viscous fit stops at
    dB = 0, the effect's definition ("lubricant viscous drag larger than modelled", interface.md section 4),
    and, on its limit, is not named; the load friction is one-sided the same way, the preload's limit is
    physical (T_fc + dT >= 0; catalog module docstring, "Limits")."""
    f = NOM.friction
    sc, model = scorer(Augment(dB=-2.0 * f.viscous), seed=2, cycles=12)
    cat = catalog(model)
    assert cat["viscous_friction"].limits == (0.0,)
    assert cat["load_friction"].limits == (0.0,)
    assert cat["preload_change"].limits == (-f.coulomb,)
    assert cat["clearance_growth"].limits == (0.0,)  # wear only widens the clearance
    r = rank(sc, cat)
    viscous = next(e for e in r.fits if e.effect.name == "viscous_friction")
    assert viscous.theta[0] == pytest.approx(0.0, abs=1e-3 * cat["viscous_friction"].scale[0])  # not below
    assert not viscous.nameable
    entry = viscous.entry()  # the ranking and the report's table say why it is not named
    assert entry.at_limit and "the data want the opposite" in effect_note(viscous, alpha=0.05)
    assert "viscous_friction" not in [e.effect.name for e in r.selected]
    # the refitted friction law reported beside the ranking keeps B >= 0, a physical limit
    refit = fit(sc, friction_refit(NOM), sc.base)
    assert refit.theta[1] == pytest.approx(-f.viscous, rel=1e-3)


def test_a_drag_smaller_than_the_twins_is_no_viscous_friction_and_a_larger_one_is():
    """A drag 60 % below the twin's B (a warm, thin grease; no catalog effect: the catalog's viscous
    friction is a drag larger than modelled) is not named as one; the same unit with the drag doubled
    names it, with its size."""
    f = NOM.friction
    sc, model = scorer(Augment(dB=-0.6 * f.viscous), seed=4, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict != "effect", [e.effect.name for e in r.selected]
    viscous = next(e for e in r.fits if e.effect.name == "viscous_friction")
    assert viscous.at_limit and not viscous.nameable
    sc, model = scorer(Augment(dB=1.0 * f.viscous), seed=4, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect" and r.effect is not None and r.effect.effect.name == "viscous_friction"
    assert r.effect.size == pytest.approx(1.0, abs=max(4.0 * r.effect.size_std, 0.1))
    # the drift test's refits of the halves leave the limit (a start on it stalled the solver there)
    drift = r.effect.drift
    assert drift is not None and min(drift.early, drift.late) > r.effect.floor, drift


def test_a_material_fit_on_a_physical_limit_is_not_named():
    """A preload relieved beyond the whole Coulomb friction (T_fc - 1.3 T_fc, no real drive has it): the
    preload fit stops at dT = -T_fc (004 eq. 9 stays dissipative), material, on its limit, and is not
    named; the report says why."""
    f = NOM.friction
    sc, model = scorer(Augment(dT_fs=-1.3 * f.coulomb, dT_fc=-1.3 * f.coulomb), seed=2, cycles=12)
    r = rank(sc, catalog(model))
    preload = next(e for e in r.fits if e.effect.name == "preload_change")
    assert preload.theta[0] == pytest.approx(-f.coulomb, rel=1e-3)
    assert preload.material and preload.at_limit and not preload.nameable
    assert "physical limit" in effect_note(preload, alpha=0.05)
    assert "preload_change" not in [e.effect.name for e in r.selected]



def test_a_clearance_smaller_than_the_unit_file_is_no_clearance_growth():
    """The contact reached 15 um earlier than the unit file's x_ag (an ECU parking the nut closer to the
    pads, a thicker pad): the effect is wear (interface.md: "axial clearance larger than nominal"), so its
    fit stops at dx = 0 and, on that limit, it is not named; the same data with the clearance 15 um
    larger name it, with its size."""
    sc, model = scorer(Augment(clearance=-1.5e-5), seed=3, cycles=12)
    r = rank(sc, catalog(model))
    growth = next(e for e in r.fits if e.effect.name == "clearance_growth")
    assert growth.theta[0] == pytest.approx(0.0, abs=1e-9) and growth.at_limit and not growth.nameable
    assert "clearance_growth" not in [e.effect.name for e in r.selected]
    sc, model = scorer(Augment(clearance=1.5e-5), seed=3, cycles=12)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect" and r.effect is not None and r.effect.effect.name == "clearance_growth"
    assert r.effect.theta[0] == pytest.approx(1.5e-5, abs=4.0 * r.effect.stderr[0] + 5e-7)

def test_a_foreign_load_relieved_preload_is_not_read_as_a_negative_viscous_drag(tmp_path):
    """The kind of miss that prompted the limits, from the independently written foreign generator: a
    double-nut preload relieved by the load (``full_b`` preload_change.relief.1, -20 % of T_fc at no load,
    gone above F_r), read before them as a viscous friction whose fit wants a B below zero. Not a blind
    test (the limits were written after this kind of miss); the foreign draws are the wider check
    (README)."""
    res = foreign_diagnosis("full_b", "preload_change.relief.1", tmp_path)
    assert res.verdict == "effect" and "preload_change" in res.effects
    assert "viscous_friction" not in res.effects


@pytest.mark.parametrize("seed", [3, 4])
def test_an_ecu_parking_anywhere_in_a_band_behind_its_target_is_no_clearance_growth(seed):
    """An ECU that parks the nut anywhere up to 16 um behind its target (one-sided, evenly: 8 um behind on
    average, more than the clearance's thermal 5 um) reads ``none``: the band its parks cover is
    measured (:mod:`.conventions`: half of it is their interquartile range, closed form from the parks the
    diagnosis sees, the first application at the recording's start having no rest before it) and the
    clearance entry becomes r_x = hypot(5 um, half-band).  One application parked 30 um off moves the
    half-band by less than 1.5 um.  The same 8 um with no spread cannot be told from wear and is named a
    clearance growth of 8 um (the documented limit).  A growth of 25 um with the scattered parks is named,
    its size the growth plus the parks' mean offset."""
    rng = np.random.default_rng(100 + seed)
    parks = -rng.uniform(0.0, 16e-6, 13)  # before each of the 12 applications and after the last [m]
    seen = parks[1:12]
    sc, model = scorer(Augment(), seed=seed, cycles=12, parks=parks)
    assert model.park_half_band == pytest.approx(np.subtract(*np.percentile(seen, [75, 25])), abs=0.05e-6)
    r = rank(sc, catalog(model))
    assert r.verdict == "none", [(e.effect.name, e.size, e.floor) for e in r.selected]
    odd = parks.copy()
    odd[6] = -30e-6
    _, model_odd = scorer(Augment(), seed=seed, cycles=12, parks=odd)
    assert abs(model_odd.park_half_band - model.park_half_band) < 1.5e-6
    sc, model = scorer(Augment(), seed=seed, cycles=12, parks=np.full(13, -8e-6))
    r = rank(sc, catalog(model))
    assert model.park_half_band < 0.1e-6
    assert r.verdict == "effect" and r.effect.effect.name == "clearance_growth"
    assert r.effect.size == pytest.approx(8e-6, abs=4.0 * r.effect.size_std + 0.3e-6)
    sc, model = scorer(Augment(clearance=2.5e-5), seed=seed, cycles=12, parks=parks)
    r = rank(sc, catalog(model))
    assert r.verdict == "effect" and r.effect.effect.name == "clearance_growth"
    assert r.effect.size == pytest.approx(2.5e-5 - np.mean(seen), abs=4.0 * r.effect.size_std + 0.3e-6)


@pytest.mark.parametrize("name", ["viscous_friction", "efficiency_variation", "stribeck"])
def test_the_sampling_bound_is_the_largest_size_change_over_every_sign_of_the_unresolved_errors(name):
    """:func:`.ranking.sampling_bound` against brute force: a fit linearised at its solution (Jacobian J of
    9 rows, the effect's parameters and two others) moves its parameters by J^+ dz for a change dz of the
    residual; every row's error up to its bound e_b with either sign (512 patterns), the size's change
    taken by finite differences of the effect's own size function, not its gradient."""
    effect = build_catalog(NOM)[name]
    theta = np.array(TRUTH[name][1], float)
    rng = np.random.default_rng(7)
    J = rng.normal(size=(9, effect.k + 2)) / np.concatenate([np.abs(theta), [1.0, 1.0]])
    bound = rng.uniform(0.0, 1.0, 9)
    f = Fit(theta, np.zeros(effect.k), Model(), {}, response=np.linalg.pinv(J)[:effect.k], bound=bound)
    eps = 1e-7
    worst = 0.0
    for signs in np.array(np.meshgrid(*[[-1.0, 1.0]] * 9)).reshape(9, -1).T:
        d_theta = np.linalg.lstsq(J, signs * bound, rcond=None)[0][:effect.k]
        change = (effect.size(theta + eps * d_theta) - effect.size(theta - eps * d_theta)) / (2 * eps)
        worst = max(worst, abs(change))
    assert sampling_bound(effect, f) == pytest.approx(worst, rel=1e-5)
    assert sampling_bound(effect, dataclasses.replace(f, response=np.zeros((0, 0)))) is None


@pytest.mark.parametrize("name", ["viscous_friction", "efficiency_variation"])
def test_a_real_refit_with_the_worst_signs_moves_the_size_by_the_sampling_bound(name, monkeypatch):
    """End to end on a 250 Hz closed-form recording: every calibration block's torque residual moved by its
    unresolved torque as the residuals show it (c_E e_b) with the sign that raises the size most, the
    effect refitted by the nonlinear least squares (nuisances and tolerances with it, from the solution):
    the size rises by the bound :func:`.ranking.sampling_bound` computes from the first fit alone."""
    sc, model = scorer(Augment(dB=1.5e-3), seed=1, rate=250.0)
    effect = catalog(model)[name]
    f = fit(sc, effect, sc.base)
    rows = sc.valid(sc.split.calibration, "torque")
    n = int(rows.sum())
    signs = np.zeros(model.blocks.size)
    signs[rows] = np.sign(size_gradient(effect, f.theta) @ f.response)[:n]
    shown = sc.transient_scale * np.hypot(model.unresolved_torque, model.ambiguous_torque)
    bound = sampling_bound(effect, f)
    assert bound is not None and bound > 0.01 * effect.size(f.theta)
    residual = model.torque_residual
    again = dataclasses.replace(effect, starts=(tuple(f.theta),))
    sizes = []
    for delta in (np.zeros(model.blocks.size), signs * shown):
        moved = lambda aug, *a, _d=delta: residual(aug, *a) + (0.0 if a else _d)  # noqa: E731
        monkeypatch.setattr(model, "torque_residual", moved)
        sizes.append(effect.size(fit(sc, again, f.model).theta))
    assert sizes[1] - sizes[0] == pytest.approx(bound, rel=0.05)


def test_held_out_rows_are_labelled_with_their_cycles_in_z_raw_order():
    """Each held-out row's label (Scorer.row_cycles, the clusters of the cycles' scale) is its block's cycle:
    z_raw's rows are rows() of all rows (torque then force, every block), and so are the labels, whatever
    the order the channels are named in, also where the two channels' rows differ."""
    sc, _ = scorer(Augment(dB=3e-3), seed=1, rate=250.0)
    h, every = sc.split.heldout, np.tile(sc.model.blocks.cycle, 2)
    cycles = sc.row_cycles(h)
    assert np.array_equal(sc.z_raw(sc.base.aug, h), sc.z_all(sc.base.aug)[sc.rows(h)])
    for order in (("torque", "force"), ("force", "torque")):
        assert np.array_equal(sc.rows(h, order), sc.rows(h))
        assert np.array_equal(sc.row_cycles(h, order), every[sc.rows(h, order)])
        assert np.array_equal(sc.row_cycles(h, order), cycles)
    # with one cycle's force rows left out (an application not released) the two channels' labels differ
    left_out = int(cycles[0])
    unreleased = types.SimpleNamespace(model=sc.model, valid=lambda mask, ch: mask & (
        sc.model.blocks.cycle != left_out) if ch == "force" else mask)  # the scorer with that application
    labels = Scorer.row_cycles(unreleased, h)  # type: ignore[arg-type]
    reverse = ("force", "torque")
    assert labels.size < cycles.size
    assert np.array_equal(Scorer.row_cycles(unreleased, h, reverse), labels)  # type: ignore[arg-type]
    assert np.array_equal(labels, every[Scorer.rows(unreleased, h, reverse)])  # type: ignore[arg-type]


def test_a_size_the_sampling_could_have_made_is_tested_by_the_improvement_and_any_other_by_the_direction(
        monkeypatch):
    """evaluate()'s test (a) against W_E, on a material drag (B + 3e-3 N m s/rad, 1.7 B) fitted for real on a
    250 Hz closed-form recording.  Its p-value is the direction test's unless its worst-case sampling change
    exceeds its margin over the floor (size - 1.645 std - floor), then the improvement test's; with the drag
    present the direction test is the stronger (V = U + |delta|^2 / (2 scale)), so the caution costs
    significance."""
    sc, model = scorer(Augment(dB=3e-3), seed=1, rate=250.0)
    effect = catalog(model)["viscous_friction"]
    before = (nominal_sse(sc), sc.gap(Model(sc.base.aug)))
    ef = evaluate(sc, effect, *before)
    zb = sc.z(base_without_own(sc, effect), sc.split.heldout)
    margin = ef.size - MATERIAL_Z * ef.size_std - ef.floor
    assert ef.material and 0.0 < ef.sampling < margin  # this fit is not cautioned: evaluate() took V
    cycles = sc.row_cycles(sc.split.heldout)  # p_cycles: the same test scaled over the held-out cycles
    assert ef.p_value == direction_p(zb, ef.z_heldout)
    assert ef.p_cycles == direction_p(zb, ef.z_heldout, cycles)
    entry = ef.entry()
    assert (entry.p_value, entry.p_value_cycles) == (ef.p_value, ef.p_cycles)
    seen: list[np.ndarray | None] = []  # the cycle labels evaluate() hands the test, row by row

    def spy(z_before: np.ndarray, z_after: np.ndarray, clusters: np.ndarray | None = None) -> float:
        seen.append(clusters)
        return direction_p(z_before, z_after, clusters)

    monkeypatch.setattr(effect_fit, "direction_p", spy)
    evaluate(sc, effect, *before)
    assert len(seen) == 2 and seen[0] is None and seen[1] is not None
    assert np.array_equal(seen[1], cycles) and seen[1].size == zb.size
    monkeypatch.setattr(effect_fit, "direction_p", direction_p)
    monkeypatch.setattr(effect_fit, "sampling_bound", lambda *_: 1.01 * margin)  # the same fit, cautioned
    cautioned_fit = evaluate(sc, effect, *before)
    assert cautioned_fit.p_value == improvement_p(zb, ef.z_heldout)
    assert cautioned_fit.p_cycles == improvement_p(zb, ef.z_heldout, cycles)
    assert evaluate(sc, effect, *before, tested=False).p_cycles is None  # an addition: not computed
    # the report says when a pass at the level rests on independent rows, and only then
    rests = effect_note(dataclasses.replace(ef, p_value=1e-4, p_cycles=0.02), alpha=0.05 / 8)
    assert "independent" in rests and "p = 0.02" in rests
    for p_value, p_cycles in ((1e-4, 1e-3), (0.01, 0.02), (1e-4, None)):
        assert "independent" not in effect_note(dataclasses.replace(ef, p_value=p_value, p_cycles=p_cycles),
                                                alpha=0.05 / 8)
    # either branch hands the cycles on: held-out residuals sharing an error along delta per cycle, where the
    # cycles' scale exceeds |delta| (here, unlike the fit's own residuals, the floor does not bind)
    delta = zb - ef.z_heldout
    _, pos = np.unique(cycles, return_inverse=True)
    shared = 3.0 * np.random.default_rng(2).normal(size=pos.max() + 1)[pos] * delta / np.linalg.norm(delta)
    zb2, za2 = zb + shared, ef.z_heldout + shared
    for branch, test in ((1.01, improvement_p), (0.99, direction_p)):
        f2 = dataclasses.replace(ef, sampling=branch * margin, z_heldout=za2)
        assert against_tolerance_p(f2, zb2, cycles) == test(zb2, za2, cycles) != test(zb2, za2)
    cautioned = dataclasses.replace(ef, sampling=1.01 * margin)
    free = dataclasses.replace(ef, sampling=0.99 * margin)
    assert sampling_caution(cautioned) and not sampling_caution(free)
    assert against_tolerance_p(cautioned, zb) == improvement_p(zb, ef.z_heldout)
    assert against_tolerance_p(free, zb) == direction_p(zb, ef.z_heldout)
    p_v, p_u = against_tolerance_p(free, zb), against_tolerance_p(cautioned, zb)
    assert p_v < p_u < 1e-3
    half = 0.5 * np.linalg.norm(zb - ef.z_heldout)  # V - U = |delta| / 2 in the normal quantiles
    assert stats.norm.isf(p_v) - stats.norm.isf(p_u) == pytest.approx(half, rel=1e-6)
    for unbounded in (dataclasses.replace(ef, sampling=None),  # no sampling bound (a pair, an extension)
                      dataclasses.replace(ef, size=ef.floor, sampling=10.0 * ef.size)):  # no margin to lose
        assert against_tolerance_p(unbounded, zb) == direction_p(zb, ef.z_heldout)

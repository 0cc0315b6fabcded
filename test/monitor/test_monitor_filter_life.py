"""Filter bank, change detection, remaining-life quantiles and ISO 3408-5 fatigue life.

References independent of the code under test: filterpy's KalmanFilter for every
component step, least squares on a line for the learned rate, Monte Carlo of the
mixture for the life quantiles, closed forms for a known state.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter

from ebm_wear_monitor.monitor import MonitorConfig, MonitorState
from ebm_wear_monitor.monitor.kalman import Bank, Hypotheses
from ebm_wear_monitor.monitor.life import (
    STATUS_DUE,
    STATUS_INSUFFICIENT,
    STATUS_OK,
    STATUS_WARN,
    fatigue_life,
    life_quantiles,
    limiting_mechanism,
    wear_life,
)
from ebm_wear_monitor.monitor.tracker import REJECTED, ClearanceTracker

LIMIT, X0, SIGMA = 0.5e-3, 0.2e-3, 1e-6  # clearance limit, nominal clearance, observation noise [m]
G_MODEL = 2.75e-11  # the wear model's growth per application [m] (twin, reference EMBU: ~1e-11)


def _track(truth, *, sigma=SIGMA, seed=0, config=None, growth=G_MODEL, budget=None, prior_width=1.0):
    """Feed observations truth_k + N(0, sigma) to a new tracker; yields (k, tracker, StepResult).
    ``prior_width`` multiplies the data-driven rate prior sigma_r0 (kalman.py)."""
    config = config or MonitorConfig()
    rng = np.random.default_rng(seed)
    tracker = ClearanceTracker.start(config, X0, config.initial_clearance_std_m ** 2, LIMIT)
    if prior_width != 1.0:
        rate_std = tracker.rate_std_m * prior_width
        tracker = ClearanceTracker(tracker.hyp, config, rate_std, Bank.prior(
            tracker.hyp, config, X0, config.initial_clearance_std_m ** 2, rate_std))
    for k, x in enumerate(truth, 1):
        result = tracker.step(growth, x + rng.normal(0.0, sigma), (budget or sigma) ** 2)
        yield k, tracker, result


def _run(truth, **kw):
    *_, (_, tracker, _) = _track(truth, **kw)
    return tracker


# ----------------------------------------------------------------------------- the filter bank
def test_every_component_step_is_the_textbook_kalman_filter():
    """predict/update of each component equals filterpy's KalmanFilter with the documented F, B, Q, H, R."""
    config = MonitorConfig(noise_scale_prior_cycles=1e9)  # noise scale stays 1: R = the budget
    hyp = Hypotheses.build(config)
    bank = Bank.prior(hyp, config, X0, 1e-8, 3e-5)
    picks = [0, 1, 2, 8, hyp.size - 1]  # model, steady, steady wandering, an exponential, const. acceleration
    refs = []
    for i in picks:
        kf = KalmanFilter(dim_x=3, dim_z=1)
        kf.x, kf.P, kf.H = bank.x[i].reshape(3, 1).copy(), bank.P[i].copy(), np.array([[1.0, 0.0, 0.0]])
        refs.append(kf)
    rng = np.random.default_rng(3)
    for k in range(40):
        g = 1e-9 * (1 + k % 3)
        z, r = X0 + 1e-6 * k + rng.normal(0, 1e-6), (1e-6) ** 2
        bank.predict(hyp, config, g)
        for i, kf in zip(picks, refs, strict=True):
            F = np.array([[1, g if hyp.model[i] else 1, 0.5 if hyp.accel[i] else 0],
                          [0, hyp.rho[i], 1 if hyp.accel[i] else 0], [0, 0, 1]], float)
            B = np.array([[0.0 if hyp.model[i] else 1.0], [0.0], [0.0]])
            kf.predict(u=np.array([[g]]), B=B, F=F, Q=np.zeros((3, 3)))
            rate_q = config.factor_drift_per_cycle if hyp.model[i] else hyp.wander[i] * abs(kf.x[1, 0])
            kf.P += np.diag([(config.growth_scatter * g) ** 2, rate_q ** 2, 0.0])
        y, S = bank.innovation(z, r)
        bank.update(config, z, r, y, S)
        for i, kf in zip(picks, refs, strict=True):
            kf.update(np.array([[z]]), R=np.array([[r]]))
            assert bank.x[i] == pytest.approx(kf.x[:, 0], rel=1e-6, abs=1e-18)
            assert bank.P[i] == pytest.approx(kf.P, rel=1e-5, abs=1e-24)


def test_steady_component_is_the_least_squares_line_with_its_prior():
    """Independent of filterpy and of the bank: with no model growth (g = 0, so Q = 0) the steady
    component's posterior is the closed-form Bayesian line fit z_k = c_0 + k r + v_k, v_k ~ N(0, R),
    with the prior c_0 ~ N(X0, P0), r ~ N(0, s^2): information Lambda = diag(1/P0, 1/s^2) + sum h h' / R,
    h = [1, k], mean Lambda^-1 (prior information + sum h z_k / R); then c_N = c_0 + N r."""
    config = MonitorConfig(noise_scale_prior_cycles=1e9)  # noise scale stays 1: R = the budget
    hyp = Hypotheses.build(config)
    steady = 1
    assert hyp.rho[steady] == 1.0 and not hyp.accel[steady] and hyp.wander[steady] == 0.0
    p0, s, r_var, n = 1e-10, 3e-5, (1e-6) ** 2, 60
    bank = Bank.prior(hyp, config, X0, p0, s)
    rng = np.random.default_rng(5)
    z = X0 + 2e-7 * np.arange(1, n + 1) + rng.normal(0.0, 1e-6, n)
    for k in range(n):
        bank.predict(hyp, config, 0.0)
        y, S = bank.innovation(z[k], r_var)
        bank.update(config, z[k], r_var, y, S)
    h = np.column_stack([np.ones(n), np.arange(1.0, n + 1)])
    info = np.diag([1.0 / p0, 1.0 / s ** 2]) + h.T @ h / r_var
    cov = np.linalg.inv(info)
    theta = cov @ (np.array([X0 / p0, 0.0]) + h.T @ z / r_var)
    to_last = np.array([[1.0, float(n)], [0.0, 1.0]])
    assert bank.x[steady, :2] == pytest.approx(to_last @ theta, rel=1e-9)
    assert bank.P[steady, :2, :2] == pytest.approx(to_last @ cov @ to_last.T, rel=1e-7)


@pytest.mark.parametrize("multiple", [0.0, 1.0, 1e3, 1e5, 1e6])
def test_learns_any_growth_rate_from_zero_to_a_million_times_the_model(multiple):
    """The learned growth is right whatever its ratio to the model; the steady component's rate has the
    least-squares standard error sigma sqrt(12 / N^3) of a line; the model component keeps weight only
    when the data agree with it."""
    rate = multiple * G_MODEL
    n = 400
    truth = X0 + rate * np.arange(1, n + 1)
    tracker = _run(truth, seed=int(multiple) % 97)
    gbar = G_MODEL
    mean, std = tracker.live.growth_rate(tracker.hyp, gbar)
    sd_ls = SIGMA * math.sqrt(12.0 / n ** 3)  # 1.4e-10 m per application
    assert abs(mean - rate) < 4.0 * max(std, sd_ls)
    assert std < max(3.0 * sd_ls, 0.1 * rate)  # the wandering-rate hypotheses widen it for fast growth
    beta = tracker.live.noise_scale  # the measured noise scale (about 1 here)
    assert math.sqrt(tracker.live.P[1, 1, 1]) == pytest.approx(sd_ls * math.sqrt(beta), rel=0.15)
    w_model = tracker.live.weights()[0]
    if rate - G_MODEL > 10 * sd_ls:
        assert w_model < 1e-6  # a model 1e3..1e6 x off is rejected, not fitted as outliers
    else:
        assert w_model > 0.5  # flat or model-like data: the informative prior keeps the model


def _learning_time(rate, seed, **kw):
    """First application from which the learned rate stays within 20 % of the truth."""
    truth = X0 + rate * np.arange(1, 401)
    bad = [k for k, tr, _ in _track(truth, seed=seed, **kw)
           if abs(tr.live.growth_rate(tr.hyp, G_MODEL)[0] - rate) > 0.2 * rate]
    return bad[-1] + 1 if bad else 1


def test_learning_time_is_set_by_the_noise_not_by_the_prior():
    """A 1000 x wider rate prior with 9:1 odds for the model enters only through the log of the Bayes
    factor (kalman.py: ln 1000 + ln 9 = 9 nats, z^2 / 2 grows as N^3): the learning time grows by less
    than 2x. Four times the noise: x 4^(2/3) = 2.5 (least squares: the rate is known to 20 % when
    0.2 r = z sigma sqrt(12 / N^3), so N ~ sigma^(2/3)). The old filter (a Gaussian prior on a factor)
    never learned a rate 1e4 x off, whatever the noise."""
    rate, seeds = 0.3e-6, range(5)
    base = np.median([_learning_time(rate, s, sigma=SIGMA) for s in seeds])
    wide = np.median([_learning_time(rate, s, sigma=SIGMA, prior_width=1e3,
                                     config=MonitorConfig(model_prior_weight=0.9)) for s in seeds])
    noisy = np.median([_learning_time(rate, s, sigma=4 * SIGMA) for s in seeds])
    assert wide / base < 2.0
    assert noisy / base == pytest.approx(4 ** (2 / 3), rel=0.3)


# ----------------------------------------------------------------------------- steps, outliers, changes
def _flat_then(change):
    """600 applications at the nominal clearance plus ``change(k)`` [m]."""
    return X0 + change(np.arange(1, 601))


def test_single_outlier_is_rejected_and_does_not_move_the_estimate():
    truth = _flat_then(lambda k: 0.0 * k)
    rng = np.random.default_rng(5)
    config = MonitorConfig()
    tracker = ClearanceTracker.start(config, X0, config.initial_clearance_std_m ** 2, LIMIT)
    outcomes = []
    for i, x in enumerate(truth[:300]):
        z = x + rng.normal(0.0, SIGMA) + (50e-6 if i == 200 else 0.0)
        outcomes.append(tracker.step(G_MODEL, z, SIGMA ** 2))
        if i == 199:
            before = tracker.live.clearance()[0]
        if i == 200:
            assert outcomes[-1].outcome == REJECTED
            assert abs(tracker.live.clearance()[0] - before) < 1e-3 * 50e-6  # moved by the model growth only
    assert sum(o.outcome == REJECTED for o in outcomes) == 1
    assert sum(o.steps + o.changes for o in outcomes) == 0


@pytest.mark.parametrize("step", [30e-6, -40e-6, 3e-6, -3e-6])
def test_a_step_of_the_clearance_is_a_step_never_growth(step):
    """Large steps (beyond the gate) by the run of rejections, small ones (3 sigma) by the GLR; neither
    is read as growth: no rate change, the estimate follows, no alarm (p05 stays above 1000)."""
    truth = _flat_then(lambda k: step * (k >= 300))
    steps = changes = 0
    for i, tracker, result in _track(truth, seed=7):
        steps += result.steps
        changes += result.changes
        if i > 300 and i % 25 == 0:
            life = wear_life(tracker.hyp, tracker.live, LIMIT, G_MODEL, observations=i, min_observations=10,
                             z=1.645, warn_cycles=1e4, due_cycles=1e3)
            assert life.cycles_p05 is None or life.cycles_p05 > 1e4, (i, life)
    assert (steps, changes) == (1, 0)
    estimate, std = tracker.live.clearance()
    assert abs(estimate - truth[-1]) < 4 * std


def test_growth_that_starts_is_a_rate_change_never_steps_nor_outliers():
    truth = _flat_then(lambda k: 0.5e-6 * np.maximum(k - 300, 0))
    run = list(_track(truth, seed=9))
    tracker = run[-1][1]
    steps, changes = sum(r.steps for *_, r in run), sum(r.changes for *_, r in run)
    assert (steps, sum(r.outcome == REJECTED for *_, r in run)) == (0, 0) and changes <= 1
    p05, p50, p95 = life_quantiles(tracker.hyp, tracker.live, LIMIT, G_MODEL, (0.05, 0.5, 0.95))
    true_rul = (LIMIT - truth[-1]) / 0.5e-6
    assert p05 < true_rul < p95 and p50 == pytest.approx(true_rul, rel=0.1)


def test_replay_from_the_saved_state_is_bit_identical():
    """The tracker's whole persistent state is (anchor bank, last records): restoring it and going on
    gives exactly the numbers of the run that never stopped, across a detected step."""
    truth = _flat_then(lambda k: 0.4e-6 * k + 3e-6 * (k >= 100))
    rng = np.random.default_rng(2)
    z = truth[:160] + rng.normal(0.0, SIGMA, 160)
    config = MonitorConfig()
    ref = ClearanceTracker.start(config, X0, config.initial_clearance_std_m ** 2, LIMIT)
    for zz in z[:110]:
        ref.step(G_MODEL, zz, SIGMA ** 2)
    resumed = ClearanceTracker.from_dict(ref.to_dict(), config, X0, LIMIT)
    for zz in z[110:]:
        a, b = ref.step(G_MODEL, zz, SIGMA ** 2), resumed.step(G_MODEL, zz, SIGMA ** 2)
        assert a == b
    for name in ("x", "P", "logw"):
        assert np.array_equal(getattr(ref.live, name), getattr(resumed.live, name))


def test_version_1_state_is_migrated_with_its_clearance_and_factor(unit):
    from ebm_wear_monitor.monitor import MonitorCore
    old = MonitorState().to_dict()
    for key in ("tracker", "clearance_steps", "growth_changes"):
        old.pop(key)
    old |= {"version": 1, "filter_x": [0.31e-3, 2.0], "filter_P": [[4e-12, 0.0], [0.0, 0.01]],
            "rejections_in_row": 2, "duty_cycles": 50, "observations": 50}
    state = MonitorState.from_dict(old)
    snap = MonitorCore(unit, state=state).snapshot()
    assert snap.clearance_estimate_m == pytest.approx(0.31e-3, rel=1e-12)
    assert snap.clearance_std_m == pytest.approx(2e-6, rel=1e-9)
    with pytest.raises(ValueError, match="version-1 filter_x"):
        MonitorState.from_dict(old | {"filter_x": [1.0]})


# ----------------------------------------------------------------------------- remaining life
def _monte_carlo(hyp, bank, gbar, n_samples=60_000, seed=1):
    """Quantiles of the first (real-valued) application count at which a sampled state's path reaches the
    limit: a scan on a log grid finds the first grid point past the limit, bisection the crossing."""
    rng = np.random.default_rng(seed)
    w = bank.weights()
    comp = rng.choice(w.size, size=n_samples, p=w)
    grid = np.geomspace(1e-2, 1e7, 400)
    first = np.full(n_samples, np.inf)
    for i in np.unique(comp):
        idx = np.flatnonzero(comp == i)
        x = rng.multivariate_normal(bank.x[i], bank.P[i], size=idx.size, method="eigh")

        def path(n, x=x, i=i):  # Y_n of every sample of component i; n of shape (k, 1) or (samples,)
            h1, h2, o = (a[..., i] for a in hyp.projection(n, gbar))
            return x[:, 0] + h1 * x[:, 1] + h2 * x[:, 2] + o

        reached = path(grid[:, None]) >= LIMIT  # (grid, samples)
        hit = reached.any(axis=0)
        j = np.argmax(reached, axis=0)
        lo, hi = np.where(j > 0, grid[np.maximum(j - 1, 0)], 0.0), grid[j]
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            past = path(mid) >= LIMIT
            lo, hi = np.where(past, lo, mid), np.where(past, mid, hi)
        first[idx] = np.where(hit, hi, np.inf)
    return np.percentile(first, [5, 50, 95])


def test_life_quantiles_match_monte_carlo_of_the_mixture():
    """A unit whose growth accelerates: several components share the weight."""
    k = np.arange(1, 121)
    truth = X0 + 0.5e-6 * (np.exp(0.01 * k) - 1) / 0.01  # 0.316 mm after 120, rate 1.7 um and rising
    tracker = _run(truth, seed=4)
    assert np.sort(tracker.live.weights())[-2] > 1e-3  # a genuine mixture
    got = life_quantiles(tracker.hyp, tracker.live, LIMIT, G_MODEL, (0.05, 0.5, 0.95))
    ref = _monte_carlo(tracker.hyp, tracker.live, G_MODEL)
    assert got == pytest.approx(ref, rel=0.005)


def test_life_of_a_known_steady_state_is_the_linear_closed_form():
    config = MonitorConfig()
    hyp = Hypotheses.build(config)
    bank = Bank.prior(hyp, config, 0.35e-3, 1e-30, 1e-20)
    bank.x[:, 1] = 0.8e-9
    bank.logw[:] = -np.inf
    bank.logw[1] = 0.0  # the steady component alone
    closed = (LIMIT - 0.35e-3) / (G_MODEL + 0.8e-9)
    got = life_quantiles(hyp, bank, LIMIT, G_MODEL, (0.05, 0.5, 0.95))
    assert got == pytest.approx([closed] * 3, rel=1e-3)


def test_status_and_no_made_up_numbers():
    config = MonitorConfig()
    hyp = Hypotheses.build(config)
    fresh = Bank.prior(hyp, config, X0, 1e-8, 3e-5)
    kw = dict(min_observations=10, z=1.645, warn_cycles=1e4, due_cycles=1e3)
    early = wear_life(hyp, fresh, LIMIT, G_MODEL, observations=3, **kw)
    assert early == type(early)(STATUS_INSUFFICIENT, None, None, None)
    flat = _run(np.full(200, X0))  # the model (f ~ N(1, 1)) keeps the weight: growth may be zero
    life = wear_life(hyp, flat.live, LIMIT, G_MODEL, observations=200, **kw)
    assert life.status == STATUS_INSUFFICIENT and life.cycles_p95 is None and life.cycles_p05 > 1e6
    growing = _run(X0 + 1e-6 * np.arange(1, 201))  # 100 applications left
    assert wear_life(hyp, growing.live, LIMIT, G_MODEL, observations=200, **kw).status == STATUS_DUE
    assert wear_life(hyp, growing.live, LIMIT, G_MODEL, observations=200,
                     **kw | {"due_cycles": 50.0}).status == STATUS_WARN
    assert wear_life(hyp, growing.live, LIMIT, G_MODEL, observations=200,
                     **kw | {"due_cycles": 5.0, "warn_cycles": 10.0}).status == STATUS_OK
    over = dataclasses.replace(growing)
    over.live.x[:, 0] = LIMIT
    assert wear_life(hyp, over.live, LIMIT, G_MODEL, observations=200, **kw) == type(early)(
        STATUS_DUE, 0.0, 0.0, 0.0)


# ----------------------------------------------------------------------------- fatigue
def test_fatigue_l10_of_constant_and_mixed_load():
    # constant 10 kN over 2 turns, C_a = 20 kN: L10 = 2^3 * 1e6 = 8e6 revolutions
    turns = 2 * 2 * math.pi
    fat = fatigue_life(20e3, 10e3 ** 3 * turns, turns, cycles=4)
    assert fat.l10_revolutions == pytest.approx(8e6, rel=1e-12)
    assert fat.cubic_mean_load_n == pytest.approx(10e3, rel=1e-12)
    assert fat.remaining_cycles == pytest.approx((8e6 - 2) / 0.5, rel=1e-12)
    # 1 turn at 5 kN and 3 turns at 15 kN: F_m = ((5^3 + 3 * 15^3) / 4)^(1/3) kN
    r1, r3 = 2 * math.pi, 6 * math.pi
    fat = fatigue_life(20e3, 5e3 ** 3 * r1 + 15e3 ** 3 * r3, r1 + r3, cycles=1)
    fm = ((5 ** 3 + 3 * 15 ** 3) / 4) ** (1 / 3) * 1e3
    assert fat.cubic_mean_load_n == pytest.approx(fm, rel=1e-12)
    assert fat.l10_revolutions == pytest.approx((20e3 / fm) ** 3 * 1e6, rel=1e-12)
    assert fatigue_life(None, 1.0, 1.0, 1).l10_revolutions is None


def test_limiting_mechanism_compares_wear_p05_with_fatigue():
    from ebm_wear_monitor.monitor.life import WearLife
    wear = WearLife(STATUS_OK, 2e5, 3e5, 4e5)
    fat_far = fatigue_life(20e3, 10e3 ** 3 * 1.0, 1.0, cycles=1)  # ~8e6 revolutions at 1 rad per cycle
    assert limiting_mechanism(wear, fat_far) == "wear"
    fat_near = fatigue_life(20e3, 60e3 ** 3 * 1e6, 1e6, cycles=1_000_000)  # L10 = 3.7e4 rev, far exceeded
    assert limiting_mechanism(wear, fat_near) == "fatigue"
    assert limiting_mechanism(WearLife(STATUS_INSUFFICIENT, None, None, None), fat_far) == "unknown"
    assert limiting_mechanism(WearLife(STATUS_DUE, 0.0, 0.0, 0.0), fat_far) == "wear"

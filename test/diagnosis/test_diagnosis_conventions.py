"""Acquisition conventions are estimated from the data and never read as effects (issue 10 item 2).

Recordings: the closed-form cycles of diag_synth (004 eq. 1-9 written out there) changed by one
convention at a time: what the diagnosis estimates must match what was applied, and the verdict on a
unit without an effect must stay ``none``.
"""

import math

import numpy as np
import pytest
from scipy.signal import lfilter

from ebm_wear_monitor.diagnosis.conventions import park_half_band
from ebm_wear_monitor.diagnosis.pipeline import analyse, residual_model
from ebm_wear_monitor.diagnosis.recording import Resampled
from ebm_wear_monitor.diagnosis.speed import WINDOW_S, local_slope
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.twin.dynamics import actuator_model

from diag_synth import synth

UNIT = load_unit()
NOM = actuator_model(UNIT)


def test_local_slope_is_exact_for_a_quadratic_on_jittered_stamps():
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.8e-3, 1.2e-3, 400))
    y = 3.0 + 2.0 * t - 5.0 * t**2
    slope, _ = local_slope(t, y, 3)
    assert np.allclose(slope, 2.0 - 10.0 * t, atol=1e-9)
    # within a group the window is one-sided at the edges and still exact
    group = (t > t[200]).astype(int)
    slope_g, _ = local_slope(t, y, 3, group)
    assert np.allclose(slope_g, 2.0 - 10.0 * t, atol=1e-9)
    # variance factor of a centred 7-point line fit with unit spacing h: 12 / (h^2 n (n^2 - 1))
    h = 1e-3
    _, f = local_slope(np.arange(50) * h, np.zeros(50), 3)
    assert f[25] == pytest.approx(12.0 / (h * h * 7 * 48), rel=1e-9)


def test_the_angle_noise_is_never_below_the_encoders_count():
    # a noise-free 13-bit encoder on the motor at 2 kHz advances a few counts a sample; about half of its
    # second differences are zero (to rounding), so whether their MAD collapses is near a coin flip: it
    # does for seed 1 (1e-16 rad before the count's floor), not for seeds 2 and 3 (about 2.1 q / sqrt(12)).
    # Each speed is off by the count's rounding either way: the noise the model carries for the speed must
    # not fall below the one it has, against the true speed (the synth's noise-free velocity)
    count = 2.0 * np.pi / (2**13 * NOM.gear_ratio)
    floor_bound = []
    for seed in (1, 2, 3):
        rec = synth(NOM, cycles=8, rate=2000.0, seed=seed, angle_quantum=count,
                    noise={"angle": 0.0, "velocity": 0.0, "axial_force": 30.0, "current": 0.03})
        model = residual_model(rec, NOM)
        conv = model.conv
        assert conv.sigma_angle >= count / math.sqrt(12.0) * (1.0 - 1e-9)
        assert conv.estimates["angle_count_rad"].value == pytest.approx(count, rel=1e-6)  # reported
        floor_bound.append(conv.sigma_angle == pytest.approx(count / math.sqrt(12.0), rel=1e-6))
        moving = model.moving
        actual = np.sqrt(np.mean((conv.speed[moving] - rec.velocity[moving]) ** 2))
        carried = np.sqrt(np.mean(conv.sigma_angle**2 * conv.speed_factor[moving]))
        assert actual / carried < 1.5, (seed, actual, carried)
        if floor_bound[-1]:  # the count's noise is the speed's: neither far above nor below it
            assert actual / carried > 0.7, (seed, actual, carried)
    assert floor_bound == [True, False, False]  # the case this test is about is among the seeds


@pytest.mark.parametrize("rate", [200.0, 500.0, 1000.0, 2000.0])
def test_an_acceleration_step_biases_the_speed_by_at_most_dA_h_over_4(rate):
    """The bound behind the unresolved-transient torque (residuals._unresolved_torque): a step dA of the
    acceleration inside the regression window (half-length h) biases the speed by at most dA h / 4; here a
    motion decelerating at dA to a stop (a kink), the true speed analytic, the stop anywhere in an interval.
    A window cut at the step (a phase run ending there) sees two exact quadratics and no bias."""
    dt = 1.0 / rate
    half = max(2, round(0.5 * WINDOW_S / dt))
    a = 800.0  # deceleration before the stop [rad/s^2]
    for frac in np.linspace(0.0, 0.9, 7):
        t = np.arange(0.0, 0.2, dt)
        t0 = 0.1 + frac * dt
        w = np.where(t < t0, a * (t0 - t), 0.0)
        angle = np.where(t < t0, -0.5 * a * (t0 - t) ** 2, 0.0)
        bias = np.abs(local_slope(t, angle, half)[0] - w).max()
        assert 0.25 * a * half * dt / 4.0 < bias <= a * half * dt / 4.0, frac
        cut = (t >= t0).astype(int)
        assert np.abs(local_slope(t, angle, half, cut)[0] - w).max() < 1e-9 * a * dt


def _lagged(x: np.ndarray, tau: float, dt: float) -> np.ndarray:
    a = math.exp(-dt / tau)
    return lfilter([1 - a], [1, -a], x, zi=[a * x[0]])[0]


def _variants(rec: Resampled) -> dict[str, Resampled]:
    dt = rec.dt
    rng = np.random.default_rng(5)
    cycles = residual_model(rec, NOM).seg.cycle
    return {
        "encoder zero": Resampled(rec.t, rec.angle - 812.4, rec.velocity, rec.axial_force, rec.current),
        "force tare": Resampled(rec.t, rec.angle, rec.velocity, rec.axial_force - 250.0, rec.current),
        "force lag 1.5 ms": Resampled(rec.t, rec.angle, rec.velocity, _lagged(rec.axial_force, 1.5e-3, dt),
                                      rec.current),
        "velocity lag 4 ms": Resampled(rec.t, rec.angle, np.interp(rec.t - 4e-3, rec.t, rec.velocity),
                                       rec.axial_force, rec.current),
        "current offset": Resampled(rec.t, rec.angle, rec.velocity, rec.axial_force, rec.current + 0.04),
        "rest angle per application": Resampled(
            rec.t, rec.angle + rng.normal(0.0, 3e-3, cycles.max() + 1)[cycles], rec.velocity,
            rec.axial_force, rec.current),
    }


@pytest.fixture(scope="module")
def base_recording():
    return synth(NOM, cycles=10, seed=4, rate=1000.0, noise={"angle": 2e-4, "velocity": 0.05,
                                                             "axial_force": 30.0, "current": 0.02})


@pytest.mark.parametrize("name", ["encoder zero", "force tare", "force lag 1.5 ms", "velocity lag 4 ms",
                                  "current offset", "rest angle per application"])
def test_a_convention_alone_is_no_effect(base_recording, name):
    rec = _variants(base_recording)[name]
    _, ranking = analyse(rec, UNIT)
    assert ranking.verdict == "none", (name, ranking.top.effect.name, ranking.top.size)


def test_conventions_are_estimated(base_recording):
    v = _variants(base_recording)
    conv = residual_model(v["force tare"], NOM).conv
    assert conv.estimates["force_tare_N"].value == pytest.approx(-250.0, abs=5.0)
    conv = residual_model(v["velocity lag 4 ms"], NOM).conv
    assert conv.estimates["velocity_lag_s"].value == pytest.approx(4e-3, abs=0.3e-3)
    assert conv.estimates["velocity_gain"].value == pytest.approx(1.0, abs=0.02)
    sc, _ = analyse(v["force lag 1.5 ms"], UNIT)
    # the discrete lag applied above, y_k = a y_(k-1) + (1 - a) x_k with a = exp(-dt / 1.5 ms), delays a
    # slow signal by a dt / (1 - a); the fit reads it as lag + skew (collinear away from kinks)
    dt = base_recording.dt
    a = math.exp(-dt / 1.5e-3)
    assert sc.base.aug.force_lag + sc.base.aug.force_skew == pytest.approx(a * dt / (1 - a), abs=0.2e-3)
    sc, _ = analyse(v["current offset"], UNIT)
    assert sc.base.aug.current_offset == pytest.approx(0.04, abs=0.01)


@pytest.mark.parametrize("n", [12, 29])
def test_the_park_half_band_and_its_std_match_fresh_draws_of_an_even_band(n):
    """Parks spread evenly over a band of width w (:mod:`.conventions`, "Where the ECU parks"): the
    estimate averages (n - 1) / (n + 1) of w / 2 (closed form: numpy's quartiles interpolate between the
    order statistics at 1 + (n - 1) / 4 and 1 + 3 (n - 1) / 4, and the k-th of n uniform order statistics
    averages k / (n + 1) of w), and its reported std (the bootstrap over the applications) is the scatter
    of the estimate over fresh draws of the band (Monte Carlo) within 30 %.  Fewer than four released
    applications: not estimated."""
    w = 16e-6
    draws = np.random.default_rng(n).uniform(-w, 0.0, (3000, n))
    q75, q25 = np.percentile(draws, [75.0, 25.0], axis=1)
    scatter = float(np.std(q75 - q25))
    est = [park_half_band(x, np.ones(n, bool)) for x in draws[:300]]
    assert all(e is not None and e.unit == "rad" for e in est)
    values = np.array([e.value for e in est if e is not None])
    stds = np.array([e.std for e in est if e is not None])
    expected = (n - 1) / (n + 1) * w / 2
    assert np.mean(values) == pytest.approx(expected, abs=3.0 * scatter / np.sqrt(values.size))
    assert 0.7 < np.mean(stds) / scatter < 1.3
    released = np.zeros(n, bool)
    released[:3] = True
    assert park_half_band(draws[0], released) is None

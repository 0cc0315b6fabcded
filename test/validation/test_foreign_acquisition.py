"""Acquisition of foreign recordings: every topic finite at every estimator and rate the sets
draw, and the PWM ripple of ``instant`` current sampling averaging to zero.

The finiteness check writes, for every (velocity estimator, velocity rate) pair that occurs in
any case set, the case whose estimator is stiffest at its rate (observer ``wn T``, ``T / tau``,
shortest window), shortened to 3 applications (the acquisition conventions are drawn before the
schedule, so they are the case's own), and reads it back with plain rosbags.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from ebm_wear_monitor.validation.foreign import Case, case_set, write_case
from ebm_wear_monitor.validation.foreign.cases import SETS, TOPIC_RATES, VELOCITY_PARAMS, realize
from ebm_wear_monitor.validation.foreign.recording import simulate_case
from ebm_wear_monitor.validation.foreign.sensors import (
    Acquisition,
    Clock,
    asynchronous_pwm,
    pwm_ripple,
    sample_times,
)
from ebm_wear_monitor.validation.foreign.unit import REFERENCE_UNIT, load_actuator

from .foreign_read import read_bag

ACT = load_actuator(REFERENCE_UNIT)


def _stiffness(kind: str, param: float, rate: float) -> float:
    """How hard an estimator is pushed at ``rate``: wn T, T / tau or 1 / N."""
    return {"tracking": param / rate, "derivative": 1.0 / (param * rate),
            "moving_average": 1.0 / param}[kind]


def _cover() -> dict[tuple[str, float], Case]:
    best: dict[tuple[str, float], tuple[float, Case]] = {}
    for name in SETS:
        for case in case_set(name):
            acq = realize(case, ACT).acq
            rate = acq.clocks["screw/velocity"].rate
            key = (acq.velocity_kind, rate)
            stiff = _stiffness(acq.velocity_kind, acq.velocity_param, rate)
            if key not in best or stiff > best[key][0]:
                best[key] = (stiff, case)
    return {key: dataclasses.replace(case, n_apps=3) for key, (_, case) in sorted(best.items())}


COVER = _cover()


def test_the_sample_covers_every_estimator_and_the_lowest_rate() -> None:
    kinds = {kind for kind, _ in COVER}
    assert kinds == set(VELOCITY_PARAMS)
    assert all((kind, 200.0) in COVER for kind in kinds)
    assert len(COVER) >= 15


@pytest.mark.slow
def test_every_topic_of_every_estimator_and_rate_is_finite(tmp_path: Path) -> None:
    """Every message finite; the recorded velocity within 35 % of the fastest speed the recorded
    angle shows, plus two encoder quanta per period of quantisation noise (the estimators divide by
    the nominal period while each instant jitters by up to 3 x 5 % of a period, so one difference
    may span 30 % more time; the observer overshoots a speed step by about 1 %). A dropped message
    must not show: the device estimated at every tick (a difference across a gap read 1.6x)."""
    for (kind, rate), case in COVER.items():
        data, truth = read_bag(write_case(case, tmp_path))
        (ns, unit), = truth["units"].items()
        for topic, sig in data.items():
            assert sig["value"].size > 0 and np.isfinite(sig["value"]).all(), (case.case_id, topic)
        ang, vel = data[f"{ns}/screw/angle"], data[f"{ns}/screw/velocity"]
        speed = np.abs(np.diff(ang["value"]) / np.diff(ang["stamp"])).max()
        quantum = unit["foreign"]["encoder"]["quantum_screw_rad"]
        assert np.abs(vel["value"]).max() <= 1.35 * speed + 2 * quantum * rate, (case.case_id, kind)


def _assert_zero_mean(ripple: np.ndarray, pp: np.ndarray, duty: np.ndarray) -> None:
    """The ripple averages to zero over all samples and within each quartile of the duty cycle,
    to within 5 standard errors of the mean of independent uniform carrier phases, and keeps its
    peak-to-peak amplitude ``pp`` (uniform over it: standard deviation ``pp / sqrt(12)``)."""

    def se(m: np.ndarray) -> float:
        return float(np.sqrt(np.sum(pp[m] ** 2) / 12.0) / m.sum())

    assert abs(ripple.mean()) <= 5 * se(np.ones(ripple.size, dtype=bool))
    driven = duty > 0.02
    quartile = np.searchsorted(np.quantile(duty[driven], [0.25, 0.5, 0.75]), duty)
    for j in range(4):
        m = driven & (quartile == j)
        assert abs(ripple[m].mean()) <= 5 * se(m), (j, ripple[m].mean(), se(m))
    on = pp > 1e-3 * pp.max()  # D strictly between 0 and 1
    share = ripple[on] / pp[on]
    assert share.min() < -0.45 and share.max() > 0.45 and np.abs(share).max() <= 0.5 + 1e-12
    assert share.std() == pytest.approx(1 / np.sqrt(12), rel=0.05)


@pytest.mark.parametrize("rate", TOPIC_RATES)
@pytest.mark.parametrize("f_nominal", [8e3, 16e3, 20e3])
def test_instant_sampling_is_asynchronous_at_every_rate(rate: float, f_nominal: float) -> None:
    """A clock without jitter (the worst case: the carrier phase then moves only by the PWM's own
    frequency and drift) at every rate a clock can have, duty swept 5-95 % for 20 s: the carrier
    at the nominal 8/16/20 kHz, a multiple of every rate, would sample one phase all along."""
    clock = Clock(rate=rate, phase=1e-4, jitter=0.0, drops=0, frame_id="adc")
    acq = Acquisition(clocks={"motor/current": clock}, encoder_side="screw", encoder_bits=20,
                      encoder_offset=0.0, velocity_kind="derivative", velocity_param=1e-3, tare=0.0,
                      noise_F=0.0, lsb_F=1.0, current_kind="instant",
                      f_pwm=asynchronous_pwm(f_nominal, rate), noise_I=0.0, lsb_I=1e-3,
                      lag_min=0.0, lag_max=0.0)
    assert abs(acq.f_pwm - f_nominal) <= rate / 2
    rng = np.random.default_rng(int(rate + f_nominal))
    t, _ = sample_times(clock, 20.0, rng)
    v_bus, inductance = 48.0, ACT.L
    E = v_bus * (0.5 + 0.45 * np.sin(2 * np.pi * 0.7 * t))
    duty = np.abs(E) / v_bus
    pp = v_bus * duty * (1 - duty) / (inductance * acq.f_pwm)
    _assert_zero_mean(pwm_ripple(acq, t, E, v_bus=v_bus, inductance=inductance, rng=rng), pp, duty)


INSTANT = [c for c in case_set("quick") if realize(c, ACT).acq.current_kind == "instant"]


@pytest.mark.slow
@pytest.mark.parametrize("case", INSTANT, ids=[c.case_id for c in INSTANT])
def test_instant_current_ripple_averages_to_zero_at_every_duty(case: Case) -> None:
    """On the true trajectory of a recording sampled by its current clock, the ripple term
    ``pp(D) tri(phi)`` averages to zero over the recording and within each quartile of the duty
    cycle D (no duty-dependent bias: the carrier phase fixed by the sample clock gave up to
    0.1 A in one quartile of stribeck.exponential.0), with the documented peak-to-peak amplitude
    ``V_bus D (1 - D) / (L f_pwm)``."""
    act, recipe, _, _, tr = simulate_case(case)
    acq, v_bus = recipe.acq, recipe.ecu.V_bus
    rng = np.random.default_rng(7)
    ticks, delivered = sample_times(acq.clocks["motor/current"], tr.t[-1], rng)
    t = ticks[delivered]
    E = np.interp(t, tr.t, tr.E)
    duty = np.clip(np.abs(E) / v_bus, 0.0, 1.0)
    pp = v_bus * duty * (1 - duty) / (act.L * acq.f_pwm)
    _assert_zero_mean(pwm_ripple(acq, t, E, v_bus=v_bus, inductance=act.L, rng=rng), pp, duty)

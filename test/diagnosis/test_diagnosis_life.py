"""Life-level gap: wear-level effects recovered from duty-cycle summaries; 000's own gap worked out."""

import numpy as np
import pytest

from ebm_wear_monitor.diagnosis.life import LifeData, diagnose_life, life_data_from_applications
from ebm_wear_monitor.validation.papers.paper000 import paper000_example


def _data(kind: str, seed: int = 0) -> LifeData:
    rng = np.random.default_rng(seed)
    n = np.arange(0, 200_000, 2_000, dtype=float)
    force = rng.choice([10e3, 15e3, 20e3], n.size)
    g = 1.4843e-10 * force / 15e3  # model growth per cycle, proportional to load (Archard)
    true = {"none": g, "wear_coefficient": 1.2 * g,
            "running_in": g + 4e-6 / 20_000 * np.exp(-n / 20_000),
            "load_dependent_wear": g * (1 + 0.8 * (force / force.mean() - 1))}[kind]
    x = np.concatenate(([0.0], np.cumsum(np.diff(n) * 0.5 * (true[1:] + true[:-1]))))
    return LifeData(n, x + rng.normal(0, 2e-7, n.size), g, force=force)


@pytest.mark.parametrize("kind", ["running_in", "load_dependent_wear"])
def test_life_effect_named(kind):
    res = diagnose_life(_data(kind))
    assert res.verdict == "effect" and res.effect == kind


def test_wear_coefficient_ties_with_ball_share():
    res = diagnose_life(_data("wear_coefficient"))
    assert res.effect in ("wear_coefficient", "ball_share")
    other = "ball_share" if res.effect == "wear_coefficient" else "wear_coefficient"
    assert other in res.near_ties
    s = next(f for f in res.ranking if f.effect == "wear_coefficient").parameters[0]
    assert s == pytest.approx(0.2, abs=0.01)


def test_life_none_on_model_data():
    assert diagnose_life(_data("none", seed=3)).verdict == "none"


def test_paper000_worked_example():
    ex = paper000_example()
    ratio = 1.65e-10 / 1.4843e-10
    assert ex["wear_coefficient"]["s"] == pytest.approx(ratio - 1)
    # ball share beta with (1 - 1/3) / (1 - beta) = ratio
    assert (2 / 3) / (1 - ex["ball_share"]["beta"]) == pytest.approx(ratio)
    assert 0.39 < ex["ball_share"]["beta"] < 0.41
    assert ex["running_in"]["A_m"] == pytest.approx((1.65e-10 - 1.4843e-10) * 200_000)


def test_monitor_summaries_become_life_data():
    # the replay's per-application table: unobservable clearances (NaN) are skipped; the model's
    # growth per cycle is its slope over the application count (a straight line: the slope itself)
    apps = {"index": np.arange(1.0, 7.0), "peak_force_n": np.full(6, 1e4),
            "clearance_model_m": 2e-4 + 3e-9 * np.arange(6.0),
            "clearance_observed_m": np.array([2e-4, np.nan, 2.1e-4, 2.2e-4, np.nan, 2.3e-4])}
    d = life_data_from_applications(apps)
    assert np.array_equal(d.n, [1.0, 3.0, 4.0, 6.0])
    assert np.allclose(d.predicted, 3e-9, rtol=1e-6, atol=0.0)
    assert np.array_equal(d.observed, [2e-4, 2.1e-4, 2.2e-4, 2.3e-4]) and d.force.size == 4


def test_summaries_with_faster_growth_name_a_scale_effect():
    rng = np.random.default_rng(3)
    n = np.arange(1.0, 41.0)
    model = 2e-4 + 1e-7 * n  # 0.1 um per application predicted
    apps = {"index": n, "peak_force_n": rng.choice([1e4, 2e4], n.size), "clearance_model_m": model,
            "clearance_observed_m": 2e-4 + 1.5e-7 * n + rng.normal(0.0, 2e-8, n.size)}
    res = diagnose_life(life_data_from_applications(apps))
    assert res.verdict == "effect" and res.effect in ("wear_coefficient", "ball_share")
    # whichever of the two tied scale effects ranks first, the Archard factor is 1.5 / 1.0 - 1
    s = next(f for f in res.ranking if f.effect == "wear_coefficient").parameters[0]
    assert s == pytest.approx(0.5, abs=0.05)

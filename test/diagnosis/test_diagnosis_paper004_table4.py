"""Paper 004's own sim-to-real gap: twin from Table 3, "real" units from Table 4's six actuators.

The twin is 004's actuator with the calculated friction of Table 3 (forward);
each recording comes from the twin's simulator with one Table 4 row as the
unit's friction (the six actuators identified by test), plus sensor noise.
The diagnosis must recover each actuator's B and G corrections (Table 4 minus
Table 3) and name a load-related effect (004 reasons 2, 3, 5: load friction or
efficiency) for actuators 1-5, and the preload (reason 4: T_fs, T_fc far below
the calculation) for actuator 6, the one the authors re-assembled.
"""

import pytest
from scipy import stats

from ebm_wear_monitor.diagnosis.pipeline import diagnose_recording
from ebm_wear_monitor.diagnosis.recording import Resampled
from ebm_wear_monitor.twin import simulate_unit
from ebm_wear_monitor.validation.papers.paper004 import TABLE3, TABLE4, paper_unit

OVERSAMPLE = 8
APPLICATIONS = 16
#: the refit's standard errors are cluster-robust over the calibration applications (every second one,
#: ``ranking.split_by_cycle``), without a small-sample factor: with G = 8 clusters the usual reference for
#: estimate/SE is Student's t with G - 1 degrees of freedom, not a normal (an approximation here: the
#: fit has as many parameters, effect, nuisances and free tolerances, as clusters). The bound is that
#: t's quantile at the normal's 3-sigma level (0.27 %), 4.5 SE. It replaced 3 SE when the measured block
#: noise moved actuator 1's dB to 3.0 SE (2.9 before); under t(7), 3 SE over these 12 checks would
#: fail about one run in five with every estimate unbiased (were the checks independent and the 5 %
#: alternative never the larger).
T_BOUND = float(stats.t.ppf(1.0 - 0.0027 / 2.0, APPLICATIONS // 2 - 1))


@pytest.fixture(scope="module")
def results():
    nominal = paper_unit()
    out = []
    for i, row in enumerate(TABLE4):
        sim = simulate_unit(paper_unit(friction=row), APPLICATIONS, demands=(8e3, 14e3, 20e3, 26e3),
                            seed=100 + i, rate_hz=500.0 * OVERSAMPLE, wear=False, hold_s=(0.2, 0.4),
                            rest_s=0.2)
        s = slice(None, None, OVERSAMPLE)
        rec = Resampled(sim.t[s], sim.angle[s], sim.velocity[s], sim.axial_force[s], sim.current[s])
        out.append(diagnose_recording(rec, nominal))
    return out


@pytest.mark.parametrize("i", range(6))
def test_b_and_g_corrections_recovered(results, i):
    p = results[i].friction_refit.fit.parameters
    t3, t4 = TABLE3["forward"], TABLE4[i]
    for key, name in (("dB", "viscous"), ("dG", "load_coefficient")):
        true = t4[name] - t3[name]
        est, se = p[key].value, p[key].stderr
        # within T_BOUND standard errors, or 5 % of the Table 3 value (the resolution asked of a refit)
        assert abs(est - true) <= max(T_BOUND * se, 0.05 * t3[name]), (i + 1, key, est, se, true)


def test_ranking_follows_the_papers_reasons(results):
    # actuators 1-5: a load-related effect (reasons 2, 3, 5) among those the data support (actuator 5 also
    # lost 35 % of T_fc, which then moves the twin more and is named first); actuator 6, re-assembled:
    # the preload (reason 4)
    for i, res in enumerate(results):
        assert res.verdict == "effect"
        if i < 5:
            assert {"load_friction", "efficiency_variation"} & set(res.effects), (i + 1, res.effects)
        else:
            assert res.effect == "preload_change"

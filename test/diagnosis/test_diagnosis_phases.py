"""Phase and cycle labels of closed-form brake cycles (diag_synth): order and count are known."""

import numpy as np

from ebm_wear_monitor.diagnosis.phases import segment
from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.twin.dynamics import actuator_model

from diag_synth import synth


def test_cycles_and_phase_order():
    nom = actuator_model(load_unit())
    rec = synth(nom, cycles=6, seed=2)
    seg = segment(rec)
    assert seg.n_cycles == 6
    for c in range(6):
        codes = seg.phase[seg.cycle == c]
        runs = codes[np.concatenate(([True], codes[1:] != codes[:-1]))]
        runs = runs[runs != Phase.IDLE]
        # each application: clearance elimination, force generation, maintenance, release, in this order
        assert list(runs) == [0, 1, 2, 3]


def test_contact_threshold_between_noise_and_force():
    nom = actuator_model(load_unit())
    rec = synth(nom, cycles=4, seed=3)
    seg = segment(rec)
    assert 5 * 30.0 / np.sqrt(5) < seg.force_on < 0.05 * rec.axial_force.max()

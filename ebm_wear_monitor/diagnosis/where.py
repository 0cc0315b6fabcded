"""Where the twin misses: residuals of each signal in each phase and over speed and force ranges.

Every block residual of :meth:`.residuals.ResidualModel.signal_residuals` is
divided by its measured noise so that signals and phases compare:

* ``current`` and ``velocity`` are the torque-channel residual R_T seen as a
  current (R_T / K_T) and as the re-anchored speed error (R_T dt / J_me): both
  are normalised by the torque channel's block noise, so they carry the same
  z-score (one balance, two units);
* ``angle`` (re-anchored angle error at the block end) by the angle error the
  torque noise makes over the block, sigma_T dt^2 / (2 J_me i_g) (a constant
  torque error R over a block of length dt moves the screw by R dt^2 / (2 J_me i_g));
* ``axial_force`` by the force channel's block noise.

The table entry is the RMS z-score of the blocks of that phase (1 = noise);
``where`` names the phase and signal with the largest one, the torque balance
named by the signal it is measured in, the current (its ``velocity`` view differs
only by the block-length weighting).  ``by_speed`` and
``by_force`` give the torque-channel RMS z-score in quartile bins of the
block's mean screw speed (moving blocks) and clamp force (blocks in contact).
"""

from __future__ import annotations

from typing import TypeVar

import numpy as np

from ebm_wear_monitor.diagnosis.ranking import Model, Scorer
from ebm_wear_monitor.domain.phases import PHASES
from ebm_wear_monitor.domain.signals import SIGNALS
from ebm_wear_monitor.schema.diagnose import ForceBin, SpeedBin, Where

B = TypeVar("B", SpeedBin, ForceBin)


def _rms(z: np.ndarray) -> float | None:
    return float(np.sqrt(np.mean(z * z))) if z.size else None


def signal_z(sc: Scorer, m: Model) -> dict[str, np.ndarray]:
    """Noise-normalised per-block residual of each signal (module docstring), the model's tolerance
    deviations included (the angle's through its torque)."""
    b, n = sc.model.blocks, sc.model.nominal
    res = sc.model.signal_residuals(m.aug)
    dt = sc.model.rec.t[b.stop] - sc.model.rec.t[b.start]
    tol = sc.D @ m.t  # every block, torque then force
    tol_t, tol_f = tol[:b.size], tol[b.size:]
    return {
        "current": -res["current"] * n.torque_constant / sc.sigma_torque + tol_t,
        "velocity": res["velocity"] * n.inertia * n.gear_ratio / (sc.sigma_torque * dt) + tol_t,
        "angle": res["angle"] * 2.0 * n.inertia * n.gear_ratio / (sc.sigma_torque * dt * dt) + tol_t,
        "axial_force": -res["axial_force"] / sc.sigma_force - tol_f,
    }


def _bins(values: np.ndarray, z: np.ndarray, record: type[B]) -> list[B]:
    """RMS z in quartile bins of ``values`` (screw speed [rad/s]: SpeedBin, clamp force [N]: ForceBin)."""
    if values.size < 8:
        return []
    edges = np.unique(np.quantile(values, [0.0, 0.25, 0.5, 0.75, 1.0]))
    idx = np.clip(np.searchsorted(edges, values, side="right") - 1, 0, edges.size - 2)
    return [record([float(edges[i]), float(edges[i + 1])], _rms(z[idx == i]), int((idx == i).sum()))
            for i in range(edges.size - 1)]


def where_table(sc: Scorer, m: Model) -> Where:
    """The ``where`` object of the diagnosis JSON (interface.md section 4, extended)."""
    b = sc.model.blocks
    z = signal_z(sc, m)
    table = {p: {s: _rms(z[s][b.phase == i]) for s in SIGNALS} for i, p in enumerate(PHASES)}
    best = max(((v, p, s) for p, row in table.items() for s, v in row.items()
                if v is not None and s != "velocity"),
               default=(None, None, None))
    contact = b.force > sc.model.seg.force_rise
    return Where(best[1], best[2], best[0], table,
                 by_speed=_bins(b.speed[b.moving], z["current"][b.moving], SpeedBin),
                 by_force=_bins(b.force[contact], z["current"][contact], ForceBin),
                 by_force_axial=_bins(b.force[contact], z["axial_force"][contact], ForceBin))

"""One recording's true trajectory: every application simulated side by side, then stitched.

Each application ``k`` starts at rest with the motor off and is simulated in its own frame (motor
angle counted from its released rest position ``rest_k``, 004 eq. 5 clamp measured from there),
so the applications of one recording run in lock-step as one batch:

1. apply + hold: the ECU follows the demand ``F_d,k`` until the release command at ``hold_k``;
2. release: from each application's state at its release command, the ECU returns toward its
   home angle plus a per-application reference error ``eps_k``, parks, and switches off.

The home angle is absolute while each application is simulated relative to its own rest, and
``rest_{k+1} = rest_k + (end of release k)``. The release is therefore run twice: a first pass
with targets ``eps_k`` predicts each application's dead-band error ``d_k``; the second pass aims at
``eps_k - rest_k(predicted)``. The stitched trajectory uses only the second pass, so it is
exactly the plant's motion; the ECU's small misjudgement of its own position is one more
imperfection of its position loop (it keeps rest angles bounded, no random walk).

Idle gaps between applications hold the final state (motor off, stuck, no force).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .ecu import Ecu, EcuConfig
from .plant import Physics, Plant
from .unit import Actuator

#: Internal integration rate of the plant [Hz] (>= 10 kHz as the brief asks).
PLANT_RATE = 10_000.0
#: Motor-off tail simulated after the release so the current decays (>= 20 L/R) [s].
OFF_TAIL = 0.03


@dataclass(frozen=True)
class Schedule:
    """What the train asks of the brake in one recording (arrays over applications)."""

    demand: np.ndarray  # clamp-force demand per application [N]
    hold: np.ndarray  # demand onset to release command [s]
    gap: np.ndarray  # motor off to the next demand onset [s]
    x_ag: np.ndarray  # true clearance per application, from that application's rest [m]
    eps: np.ndarray  # ECU position-reference error at the screw per application [rad]
    lead_in: float  # idle before the first demand [s]


@dataclass
class Trajectory:
    """The true, continuous (``PLANT_RATE`` grid) signals of a recording; times from its start."""

    t: np.ndarray  # [s]
    theta: np.ndarray  # motor angle, absolute (nut rest of application 0 = 0) [rad]
    q: np.ndarray  # screw-side angle referred to the motor (= theta without backlash) [rad]
    w: np.ndarray  # motor speed [rad/s]
    i: np.ndarray  # armature current [A]
    E: np.ndarray  # armature voltage, PWM average [V]
    F: np.ndarray  # true clamp force [N]
    f_cell: np.ndarray  # load-cell output after its lag, before tare and noise [N]
    rest: np.ndarray  # nut (screw-side) angle at rest before each application, motor rad [rad]
    gap_end: np.ndarray  # play theta - q left at the end of each application [rad]
    onset: np.ndarray  # demand onset time of each application [s]
    release: np.ndarray  # release command time [s]
    off: np.ndarray  # bridge switched off [s]
    contact: np.ndarray  # first instant with clamp force > 0 [s]
    unload: np.ndarray  # last instant with clamp force > 0 [s]
    peak_force: np.ndarray  # largest true clamp force of each application [N]
    held_force: np.ndarray  # true clamp force at the release command [N]
    stitch_error: dict | None = None  # see :func:`simulate` (None: exact, nothing to stitch)


def onset_times(sched: Schedule, cfg: EcuConfig) -> tuple[np.ndarray, float]:
    """Demand onset of every application and the recording length [s], as :func:`simulate`
    lays them out (known before simulating: every segment length is fixed by the schedule)."""
    n_hold = np.round(sched.hold * PLANT_RATE).astype(int)
    n_rel = round((cfg.t_pos + cfg.t_park + OFF_TAIL) * PLANT_RATE)
    n_gap = np.round(sched.gap * PLANT_RATE).astype(int)
    ends = round(sched.lead_in * PLANT_RATE) + np.cumsum(n_hold + n_rel + n_gap)
    starts = np.concatenate([[round(sched.lead_in * PLANT_RATE)], ends[:-1]])
    return starts / PLANT_RATE, float(ends[-1]) / PLANT_RATE


def _run(plant: Plant, ecu: Ecu, n_steps: int, *, every: int, control,
         save_at: np.ndarray | None = None) -> tuple[dict[str, np.ndarray], list]:
    """Step ``plant`` ``n_steps`` times with ``control(t, th, im, fm) -> E`` every ``every`` steps.

    Returns the recorded rows (``n_steps x n``) and, if ``save_at`` (one step count per
    application) is given, each application's plant state after that many steps.
    """
    n = plant.theta.size
    out = {k: np.empty((n_steps, n)) for k in ("theta", "q", "w", "i", "E", "F", "f_cell")}
    tare = plant.f_cell.copy()
    E = np.zeros(n)
    saved: list[tuple[np.ndarray, ...] | None] = [None] * n
    due: dict[int, list[int]] = {}
    if save_at is not None:
        for k, s in enumerate(save_at):
            due.setdefault(int(s), []).append(k)
    t0 = plant.t
    for s in range(n_steps):
        if s in due:
            state = plant.state()
            for k in due[s]:
                saved[k] = tuple(x[k] for x in state)
        if s % every == 0:
            th, im, fm = ecu.measure(plant.theta, plant.i, plant.f_cell, tare)
            E = control(plant.t - t0, th, im, fm)
        plant.step(E)
        out["theta"][s], out["q"][s], out["w"][s] = plant.theta, plant.q, plant.w
        out["i"][s], out["E"][s], out["F"][s], out["f_cell"][s] = plant.i, E, plant.F, plant.f_cell
    return out, saved


def _release(plant: Plant, ecu: Ecu, saved: list, target: np.ndarray) -> dict[str, np.ndarray]:
    """Run the release of every application from its saved state toward ``target`` [rad]."""
    cols = [np.array([s[j] for s in saved]) for j in range(5)]
    plant.set_state(*cols[:4], f_cell=cols[4], t=0.0)
    ecu.reset()
    ecu.w_est = cols[2].copy()
    cfg = ecu.cfg
    steps = round((cfg.t_pos + cfg.t_park + OFF_TAIL) * PLANT_RATE)
    rows, _ = _run(plant, ecu, steps, every=max(1, round(PLANT_RATE / cfg.rate)),
                   control=lambda t, th, im, fm: ecu.release(t, target, th, im, fm))
    return rows


def _once(act: Actuator, phys: Physics, cfg: EcuConfig, sched: Schedule, *, cell_lag: float,
          seed: int, origin: np.ndarray, gap0: np.ndarray) -> Trajectory:
    """One simulation of every application given where each starts (see the module docstring)."""
    dt = 1.0 / PLANT_RATE
    n = len(sched.demand)
    seeds = np.random.SeedSequence(seed).spawn(3)

    def plant() -> Plant:
        return Plant(act, sched.x_ag, dt, phys, cell_lag=cell_lag, origin=origin, gap0=gap0)

    apply_plant = plant()
    ecu = Ecu(cfg, act, n, np.random.default_rng(seeds[0]))
    n_hold = np.round(sched.hold * PLANT_RATE).astype(int)
    demand = np.asarray(sched.demand, dtype=float)
    apply_rows, saved = _run(apply_plant, ecu, int(n_hold.max()) + 1,
                             every=max(1, round(PLANT_RATE / cfg.rate)),
                             control=lambda t, th, im, fm: ecu.apply(t, demand, th, im, fm),
                             save_at=n_hold)
    eps_m = sched.eps * act.i_g
    first = _release(plant(), Ecu(cfg, act, n, np.random.default_rng(seeds[1])), saved, eps_m)
    dead = first["theta"][-1] - eps_m  # dead-band error of each application's park (pass 1)
    rest_pred = np.zeros(n)
    rest_pred[1:] = eps_m[:-1] + dead[:-1]
    rel = _release(plant(), Ecu(cfg, act, n, np.random.default_rng(seeds[2])), saved,
                   eps_m - rest_pred)
    return _stitch(sched, apply_rows, n_hold, rel=rel, idle_cell=apply_plant.cell_output(
        np.zeros(n)), gap0=gap0)


def simulate(act: Actuator, phys: Physics, cfg: EcuConfig, sched: Schedule, *, cell_lag: float,
             seed: int) -> Trajectory:
    """Simulate every application of ``sched`` and stitch them into one trajectory.

    When an application depends on where the previous one left the drive (angle-periodic effects,
    backlash), the recording is simulated twice: the second run starts each application at the
    rest angle and play of the first. ``Trajectory.stitch_error`` reports what remains: the
    largest jump of the motor angle at an application start [rad] and the largest difference
    between the rest angle a hook assumed and the simulated one [rad].
    """
    n = len(sched.demand)
    zeros = np.zeros(n)
    tr = _once(act, phys, cfg, sched, cell_lag=cell_lag, seed=seed, origin=zeros, gap0=zeros)
    if phys.needs_history:
        origin, gap0 = tr.rest.copy(), np.concatenate([[0.0], tr.gap_end[:-1]])
        tr = _once(act, phys, cfg, sched, cell_lag=cell_lag, seed=seed, origin=origin, gap0=gap0)
        tr.stitch_error = {"motor_angle_jump_rad": float(np.max(np.abs(
            gap0[1:] - tr.gap_end[:-1]), initial=0.0)),
            "origin_error_rad": float(np.max(np.abs(tr.rest - origin)))}
    return tr


def _stitch(sched: Schedule, apply_rows: dict, n_hold: np.ndarray, *, rel: dict,
            idle_cell: np.ndarray, gap0: np.ndarray) -> Trajectory:
    """Lay the applications end to end on one grid: lead-in, then apply + hold, release and
    idle gap of each, angles shifted by the nut's rest angle each application started from
    (the motor starts ``gap0`` ahead of it)."""
    dt = 1.0 / PLANT_RATE
    n = len(sched.demand)
    n_rel = rel["theta"].shape[0]
    n_gap = np.round(sched.gap * PLANT_RATE).astype(int)
    n_lead = round(sched.lead_in * PLANT_RATE)
    total = n_lead + int(np.sum(n_hold + n_rel + n_gap))
    keys = ("theta", "q", "w", "i", "E", "F", "f_cell")
    sig = {k: np.empty(total) for k in keys}
    rest, gap_end = np.zeros(n), np.zeros(n)
    onset, release, off = np.zeros(n), np.zeros(n), np.zeros(n)
    pos = 0

    def idle(count: int, theta: float, q: float, cell: float) -> None:
        nonlocal pos
        for k in keys:
            sig[k][pos:pos + count] = 0.0
        sig["theta"][pos:pos + count], sig["q"][pos:pos + count] = theta, q
        sig["f_cell"][pos:pos + count] = cell
        pos += count

    idle(n_lead, gap0[0], 0.0, idle_cell[0])
    for k in range(n):
        onset[k] = pos * dt
        h = n_hold[k]
        for key in keys:
            seg_a = apply_rows[key][:h, k]
            seg_r = rel[key][:, k]
            if key in ("theta", "q"):
                seg_a, seg_r = seg_a + rest[k], seg_r + rest[k]
            sig[key][pos:pos + h] = seg_a
            sig[key][pos + h:pos + h + n_rel] = seg_r
        release[k] = (pos + h) * dt
        pos += h + n_rel
        off[k] = pos * dt - OFF_TAIL
        gap_end[k] = sig["theta"][pos - 1] - sig["q"][pos - 1]
        if k + 1 < n:
            rest[k + 1] = sig["q"][pos - 1]
        idle(n_gap[k], sig["theta"][pos - 1], sig["q"][pos - 1], sig["f_cell"][pos - 1])
    t = np.arange(total) * dt
    contact, unload, peak, held = (np.zeros(n) for _ in range(4))
    for k in range(n):
        lo, hi = round(onset[k] / dt), round(off[k] / dt)
        loaded = np.flatnonzero(sig["F"][lo:hi] > 0.0)
        contact[k] = t[lo + loaded[0]] if loaded.size else np.nan
        unload[k] = t[lo + loaded[-1]] if loaded.size else np.nan
        peak[k] = sig["F"][lo:hi].max()
        held[k] = sig["F"][round(release[k] / dt) - 1]
    return Trajectory(t=t, theta=sig["theta"], q=sig["q"], w=sig["w"], i=sig["i"], E=sig["E"], F=sig["F"],
                      f_cell=sig["f_cell"], rest=rest, gap_end=gap_end, onset=onset, release=release, off=off,
                      contact=contact, unload=unload, peak_force=peak, held_force=held)

"""One recording end to end: simulate, acquire, write ``OUT/<case>/bag`` and ``OUT/<case>/truth.json``."""

from __future__ import annotations

import json
import shutil
import time
from pathlib import Path

import numpy as np

from . import sensors
from .bag import TOPICS, write_bag
from .cases import Case
from .effects import realise
from .plant import Nominal
from .world import simulate


def acquire(
    case: Case, nom: Nominal, d, rng: np.random.Generator
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Sampled topics (stamps [s], values) of a dense record under the case's conventions."""
    cv, T = case.conv, float(d.t[-1])
    gain = realise(
        case.effect,
        case.magnitude or 0.0,
        nom,
        n_app=len(case.schedule),
        T_rec=1.0,
        rng=np.random.default_rng(0),
    ).force_gain
    out = {}
    for key in TOPICS:
        gap = cv["gap_s"] if cv["gap_topic"] == key else 0.0
        t = sensors.stamps(
            case.rates[key], T, rng, jitter=cv["stamp_jitter_s"], drop=cv["drop_fraction"], gap=gap
        )
        if key == "angle":
            v = sensors.angle(d, t, cv, nom.i_g)
        elif key == "velocity":
            v = sensors.velocity(d, t, cv, nom.i_g)
        elif key == "force":
            v = sensors.force(d, t, cv, gain, rng)
        else:
            v = sensors.current(d, t, cv, rng)
        out[key] = (t, v)
    return out


def truth(case: Case, d, n_msgs: int, nom: Nominal) -> dict:
    """truth.json content."""
    real = realise(
        case.effect,
        case.magnitude or 0.0,
        nom,
        n_app=len(case.schedule),
        T_rec=float(d.t[-1]),
        rng=np.random.default_rng(case.seed + 7),
    )
    return {
        "case": case.case_id,
        "kind": case.kind,
        "effect": case.effect,
        "form": case.form,
        "magnitude": case.magnitude,
        "controller": case.ctrl,
        "rates_hz": case.rates,
        "namespace": case.namespace,
        "conventions": case.conv | {"frame_ids": case.frames},
        "storage": case.storage,
        "world": "third",
        "effect_detail": real.detail,
        "duration_s": round(float(d.t[-1]), 3),
        "messages": n_msgs,
        "plant_step_s": case.h,
        "applications": d.apps,
    }


def write_case(case: Case, out: Path, nom: Nominal) -> tuple[float, int]:
    """Write one case atomically (temp dir, then rename). Returns (seconds, message count)."""
    t0 = time.time()
    final = out / case.case_id
    tmp = out / f".{case.case_id}.tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir(parents=True)
    d = simulate(case, nom)
    rng = np.random.default_rng(case.seed + 11)
    series = acquire(case, nom, d, rng)
    n = write_bag(
        tmp / "bag",
        case.namespace,
        series,
        frames=case.frames,
        storage=case.storage,
        epoch_s=case.conv["epoch_s"],
        log_lag_max_s=case.conv["log_lag_max_s"],
        rng=rng,
    )
    (tmp / "truth.json").write_text(json.dumps(truth(case, d, n, nom), indent=1))
    if final.exists():
        shutil.rmtree(final)
    tmp.rename(final)
    return time.time() - t0, n

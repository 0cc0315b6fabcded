"""Case set of the third world, deterministic from a seed (one RNG stream per case index)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .effects import CATALOG, FORMS, OUTSIDE, draw_magnitude
from .plant import Nominal

TOPIC_KEYS = ("angle", "velocity", "force", "current")
CTRL_NAMES = ("cascade_force_pi", "profile_position", "bang_bang_p_hold")


@dataclass
class Case:
    """One recording: effect, ECU, duty schedule, acquisition conventions."""

    case_id: str
    kind: str  # "none" | "effect" | "outside"
    effect: str | None
    magnitude: float | None
    seed: int
    ctrl: dict
    schedule: list[dict]
    conv: dict
    rates: dict[str, int]
    namespace: str
    frames: dict[str, str]
    storage: str
    h: float = 2.5e-4
    extra: dict = field(default_factory=dict)

    @property
    def form(self) -> str | None:
        """Equation of the effect (README table)."""
        return FORMS.get(self.effect) if self.effect else None


def _ctrl(name: str, rng: np.random.Generator, nom: Nominal) -> dict:
    u = rng.uniform
    p: dict = {"rest_tol": round(u(0.02, 0.04), 4)}
    if name == "cascade_force_pi":
        p |= {
            "f_F": u(3.0, 6.0),
            "w_max": u(22.0, 32.0),
            "f_w": u(12.0, 25.0),
            "ff": u(0.6, 1.0),
            "tol": u(0.01, 0.03),
            "f_th": u(2.0, 4.0),
        }
    elif name == "profile_position":
        p |= {
            "v_max": u(18.0, 30.0),
            "a_max": u(1500.0, 3500.0),
            "f_w": u(12.0, 25.0),
            "f_th": u(5.0, 10.0),
            "ff": u(0.5, 0.9),
            "k_trim": float(rng.choice([0.0, 0.0, 1.0, 2.0])),
            "F_learn": u(500.0, 1200.0),
        }
    else:
        p |= {
            "k_app": u(0.8, 1.0),
            "margin": u(0.0, 0.05),
            "kpF": u(4e-4, 8e-4),
            "kd": u(0.08, 0.15),
            "bias": u(0.0, 0.3),
            "k_rel": u(0.4, 0.8),
            "kp_th": u(6.0, 12.0),
        }
    p = {k: round(float(v), 6) for k, v in p.items()}
    return {
        "name": name,
        "rate_hz": int(rng.choice([1000, 2000])),
        "U_bus": float(rng.choice([36.0, 42.0, 48.0])),
        "i_lim": round(float(u(6.0, 8.0)), 3),
        "params": p,
        "contact_err": round(float(rng.normal(0, 0.03)), 5),
    }


def _schedule(rng: np.random.Generator) -> list[dict]:
    n = int(rng.integers(20, 31))
    walk = np.cumsum(rng.normal(0, 0.004, n))  # ECU rest-target creep [motor rad]
    rest0 = rng.normal(0, 0.01)
    return [
        {
            "F_d": round(float(rng.uniform(5e3, 30e3)), 1),
            "hold": round(float(rng.uniform(0.3, 2.0)), 3),
            "idle": round(float(rng.uniform(0.5, 3.0)), 3),
            "rest": round(float(rest0 + walk[k]), 5),
        }
        for k in range(n)
    ]


def _conventions(rng: np.random.Generator, nom: Nominal, force_motor_encoder: bool) -> dict:
    u = rng.uniform
    side = "motor" if force_motor_encoder or rng.random() < 0.5 else "screw"
    counts = (
        int(rng.choice([4096, 8192, 16384])) if side == "motor" else int(rng.choice([2**16, 2**17, 2**18]))
    )
    lsb = 2 * np.pi / (counts * (nom.i_g if side == "motor" else 1.0))
    vm = str(rng.choice(["observer", "mt_edge_timing", "filtered_difference"]))
    return {
        "encoder_side": side,
        "encoder_counts_per_rev": counts,
        "angle_lsb_rad": float(lsb),
        "angle_offset_rad": round(float(u(-60, 60)), 6),
        "angle_positive": "apply",
        "velocity_method": vm,
        "velocity_bw_hz": round(float(u(40, 150)), 2),
        "velocity_tau_s": round(float(u(1e-3, 5e-3)), 5),
        "velocity_timeout_s": round(float(u(5e-3, 2e-2)), 4),
        "force_lp_hz": round(float(u(80, 400)), 1),
        "force_lp_order": int(rng.choice([1, 2])),
        "force_tare_N": round(float(u(-150, 150)), 2),
        "force_noise_N": round(float(u(5, 30)), 2),
        "force_lsb_N": float(rng.choice([0.5, 1.0, 2.0])),
        "force_compressive": "positive",
        "current_mode": str(rng.choice(["sampled", "averaged"])),
        "current_gain": round(float(u(0.99, 1.01)), 5),
        "current_offset_A": round(float(u(-0.04, 0.04)), 5),
        "current_noise_A": round(float(u(0.005, 0.02)), 5),
        "stamp_jitter_s": round(float(u(0, 60e-6)), 7),
        "drop_fraction": round(float(u(0, 3e-3)), 5),
        "gap_s": round(float(u(5e-3, 3e-2)), 4) if rng.random() < 0.5 else 0.0,
        "gap_topic": str(rng.choice(TOPIC_KEYS)),
        "log_lag_max_s": round(float(u(1e-4, 1e-3)), 6),
        "epoch_s": round(float(1.70e9 + u(0, 3e7)), 3),
    }


def _namespace(rng: np.random.Generator) -> tuple[str, dict[str, str]]:
    a, b, e = (int(x) for x in rng.integers(1, 12, 3))
    pat = int(rng.integers(0, 4))
    ns = [
        f"/vehicle{a}/bogie{b % 2 + 1}/embu{e % 4 + 1}",
        f"/train{a}/car{b}/embu{e % 4 + 1}",
        f"/embu{e}",
        f"/fleet/unit{a:03d}/brake{b}",
    ][pat]
    tag = ns.strip("/").replace("/", "_")
    frames = {
        "angle": f"{tag}_screw",
        "velocity": f"{tag}_screw",
        "force": f"{tag}_load_cell",
        "current": f"{tag}_motor",
    }
    if rng.random() < 0.4:
        frames = dict.fromkeys(TOPIC_KEYS, "embu_link")
    return ns, frames


def _rates(rng: np.random.Generator) -> dict[str, int]:
    opts, w = [250, 500, 1000, 2000], [0.1, 0.25, 0.4, 0.25]
    r = {k: int(rng.choice(opts, p=w)) for k in TOPIC_KEYS}
    if rng.random() < 0.5:
        r["velocity"] = r["angle"]
    return r


def default_cases(nom: Nominal, seed: int = 3) -> list[Case]:
    """12 healthy + 8 catalog effects x 2 + 4 outside effects x 2 = 36 cases."""
    plan: list[tuple[str, str, str | None, int]] = [
        ("none", f"healthy_{k + 1:02d}", None, k) for k in range(12)
    ]
    plan += [("effect", f"{e}_{j + 1}", e, j) for e in CATALOG for j in range(2)]
    plan += [("outside", f"{e}_{j + 1}", e, j) for e in OUTSIDE for j in range(2)]
    cases = []
    for idx, (kind, cid, eff, j) in enumerate(plan):
        rng = np.random.default_rng([seed, idx])
        mag = draw_magnitude(eff, rng, half=j, sign=1 if j == 0 else -1) if eff else None
        ns, frames = _namespace(rng)
        cases.append(
            Case(
                case_id=cid,
                kind=kind,
                effect=eff,
                magnitude=mag,
                seed=seed * 1000 + idx,
                ctrl=_ctrl(CTRL_NAMES[idx % 3], rng, nom),
                schedule=_schedule(rng),
                conv=_conventions(rng, nom, eff == "backlash"),
                rates=_rates(rng),
                namespace=ns,
                frames=frames,
                storage="sqlite3" if idx % 2 == 0 else "mcap",
            )
        )
    return cases

"""Typed, validated view of one EMBU unit parameter file (interface.md section 3).

A unit file describes one EMBU design (and optionally one unit's calibrated
values). Everything is SI: m, N, Pa, kg, s, rad (angles in the file end in
``_deg`` and are degrees). Loading validates every value and raises
:class:`ParamError` with one line naming the file, the key and the problem.

Each tool reads only the blocks it uses (interface.md section 3): ``load_unit(path,
blocks=CONTACT_BLOCKS)`` validates ``ball_screw`` and ``materials`` and nothing else, so paper
003's ball screw (no lubricant, no actuator) works with ``calc contact``. A block that was not
read is a :class:`MissingBlock` (``actuator``: None); touching it raises the one-line
:class:`ParamError` naming the block, never an AttributeError deep inside a model.
"""

from __future__ import annotations

import copy
import hashlib
import json
import math
from dataclasses import asdict, dataclass, field, fields
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeVar, overload

import yaml

from ebm_wear_monitor.errors import InputError

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

REFERENCE_UNITS = {"embu_000": "embu_000.yaml", "screw_003": "screw_003.yaml"}
#: blocks of a unit file (interface.md section 3); ``monitor`` is optional everywhere (defaults)
BLOCKS = ("ball_screw", "materials", "lubricant", "wear", "actuator", "monitor")
#: what the Hertz contact needs (calc contact; 000 eq. 1-7, 003 eq. 1-17)
CONTACT_BLOCKS = ("ball_screw", "materials")
#: what the wear model needs (calc wear, the monitor core: node, replay, fleet; 000 eq. 5-23)
WEAR_BLOCKS = ("ball_screw", "materials", "lubricant", "wear")
#: what the actuator model of 004 needs (calc actuator, the diagnosis)
ACTUATOR_BLOCKS = ("ball_screw", "actuator")


#: largest boundary friction coefficient mu_a accepted (000 eq. 14) [-]: lubricated steel on steel is
#: 0.05-0.15; above ~0.3 the friction angles of eq. 15 (atan mu_s + atan mu_n) tilt the two contact
#: angles apart until the screw angle nears zero and the Fig. 6 solve converges to unphysical states
MAX_BOUNDARY_FRICTION = 0.3


class ParamError(InputError):
    """A unit parameter file is missing a key, has a wrong type or an impossible value."""


@dataclass(frozen=True)
class BallScrew:
    """Ball-screw geometry (000 Table 2, 003 Table 1)."""

    ball_radius: float  # r_b [m]
    pitch_diameter: float  # D_m, nominal (pitch-circle) diameter [m]
    lead: float  # l, axial advance per screw turn [m]
    screw_conformity: float  # f_s = r_s / (2 r_b) [-], > 0.5
    nut_conformity: float  # f_n = r_n / (2 r_b) [-], > 0.5
    effective_balls: int  # Z, loaded balls (000 eq. 5) [-]
    contact_angle_deg: float  # alpha_0, unloaded contact angle [deg]
    helix_angle_deg: float | None = None  # phi [deg]; derived from lead and D_m when None
    dynamic_load_rating: float | None = None  # C_a (ISO 3408-5) [N]

    @property
    def helix_angle(self) -> float:
        """Helix angle phi [rad]: given, or tan(phi) = l / (pi D_m)."""
        if self.helix_angle_deg is not None:
            return math.radians(self.helix_angle_deg)
        return math.atan(self.lead / (math.pi * self.pitch_diameter))

    @property
    def contact_angle(self) -> float:
        """Unloaded contact angle alpha_0 [rad]."""
        return math.radians(self.contact_angle_deg)

    @property
    def screw_groove_radius(self) -> float:
        """r_s = f_s * 2 r_b [m]."""
        return self.screw_conformity * 2.0 * self.ball_radius

    @property
    def nut_groove_radius(self) -> float:
        """r_n = f_n * 2 r_b [m]."""
        return self.nut_conformity * 2.0 * self.ball_radius


@dataclass(frozen=True)
class Material:
    """Isotropic elastic material; hardness and yield strength for raceways."""

    elastic_modulus: float  # E [Pa]
    poisson_ratio: float  # nu [-]
    hardness: float | None = None  # H [Pa]
    yield_strength: float | None = None  # sigma_s, compressive yield limit [Pa] (000 eq. 20)
    density: float = 7850.0  # rho [kg/m^3] (ball mass in 000 eq. 12)


@dataclass(frozen=True)
class Materials:
    ball: Material
    screw: Material
    nut: Material
    composite_roughness: float  # R_A [m] (000 eq. 6-7)
    asperity_radius: float | None = None  # mean asperity summit radius [m] (000 eq. 6-7, "asperity" reading)


@dataclass(frozen=True)
class Lubricant:
    viscosity: float  # eta_0, dynamic viscosity at ambient pressure [Pa s]
    pressure_viscosity: float  # alpha', pressure-viscosity coefficient [m^2/N]


@dataclass(frozen=True)
class WearParams:
    k_slip: float  # Archard dimensionless wear constant (000 eq. 20) [-]
    raceway_share: float  # share of the wear depth taken by the raceways (000 Sec. 4.1: 2/3) [-]
    boundary_friction: float  # mu_a, asperity (boundary) friction coefficient (000 eq. 14), <= 0.3 [-]


@dataclass(frozen=True)
class Motor:
    torque_constant: float  # K_T [N m / A]
    back_emf_constant: float  # K_e [V s / rad]
    resistance: float  # R [ohm]
    inductance: float  # L [H]
    inertia: float  # J_m, rotor inertia [kg m^2]
    # T_c, continuous stall torque (004 eq. 17) [N m]; 004 does not print it: the default is the
    # value its 37.30 kN friction-free maximum clamp force implies (README.md, paper 004 item 3)
    continuous_stall_torque: float = 2.939


@dataclass(frozen=True)
class Friction:
    """004 eq. 9 friction model, referred to the motor shaft."""

    static: float  # T_fs [N m]
    coulomb: float  # T_fc [N m]
    viscous: float  # B [N m s / rad]
    load_coefficient: float  # G [N m / N]


@dataclass(frozen=True)
class Actuator:
    """004 Table 1 actuator parameters."""

    gear_ratio: float  # i_g, motor turns per screw turn [-]
    motor: Motor
    screw_inertia: float  # J_s [kg m^2]
    gear_inertia: float  # J_g, referred to the motor [kg m^2]
    nut_mass: float  # m_n [kg]
    clearance: float  # x_ag, nominal brake clearance [m]
    stiffness: float  # K_b, clamp stiffness (004 eq. 6) [N/m]
    friction: Friction
    # E_amax, peak armature voltage of the drive (004 eq. 11) [V]; not printed in 004: 53 V reproduces
    # its Fig. 2a (+11 % gap-closing time) and the 40 rad/s top speed of Fig. 5a (README.md, paper 004 item 4)
    supply_voltage: float = 53.0
    current_limit: float = 8.0  # armature current limit of the drive [A]


@dataclass(frozen=True)
class MonitorParams:
    """Remaining-life thresholds people act on (monitor/life.py: status)."""

    clearance_limit: float = 0.5e-3  # x_ag at which maintenance is due [m]
    # p05 remaining brake applications at or below which the status is "warn" [-]: 10,000 is about
    # 25 days of a railway EMBU at 400 applications a day, time to plan the exchange (ASSUMED)
    warn_cycles: float = 10000.0
    # ... "due" [-]: 1,000 is 2-3 days at 400 a day, the unit should be exchanged now (ASSUMED)
    due_cycles: float = 1000.0


class MissingBlock:
    """Stands for a unit-file block that was not read: absent from the file, or not needed by the
    tool that loaded it. Falsy; any attribute raises the one-line :class:`ParamError`."""

    def __init__(self, block: str, where: str) -> None:
        self._message = f"{where}: missing or non-mapping section '{block}'"

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):  # copy, pickle and friends probe dunders: a normal miss
            raise AttributeError(name)
        raise ParamError(self._message)

    def __bool__(self) -> bool:
        return False

    def __repr__(self) -> str:
        return f"MissingBlock({self._message!r})"


@dataclass(frozen=True)
class UnitParams:
    """One unit file, validated. ``raw`` keeps the whole parsed mapping.

    Blocks not read (see :data:`BLOCKS`) are :class:`MissingBlock` (``actuator``: None).
    """

    ball_screw: BallScrew
    materials: Materials | MissingBlock
    lubricant: Lubricant | MissingBlock
    wear: WearParams | MissingBlock
    actuator: Actuator | None
    monitor: MonitorParams
    name: str = "unit"
    raw: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)

    def require_actuator(self) -> Actuator:
        """The ``actuator`` block, which the twin needs (:class:`ParamError`, one line, when not read)."""
        if self.actuator is None:
            raise ParamError(f"{self.name}: the unit file has no 'actuator' block; the twin needs one")
        return self.actuator

    def digest(self) -> str:
        """Stable hash of every physical value (for caches keyed by the parameter set)."""
        payload = {k: v for k, v in asdict(self).items() if k not in ("raw", "name")}
        text = json.dumps(payload, sort_keys=True, default=repr)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


# --------------------------------------------------------------------------- loading


def _section(data: dict[str, Any], key: str, where: str) -> dict[str, Any]:
    value = data.get(key)
    if not isinstance(value, dict):
        raise ParamError(f"{where}: missing or non-mapping section '{key}'")
    return value


@overload
def _number(sec: dict[str, Any], key: str, where: str, *, required: Literal[True] = ...,
            positive: bool = ..., nonnegative: bool = ..., lo: float | None = ..., hi: float | None = ...,
            default: float | None = ...) -> float: ...
@overload
def _number(sec: dict[str, Any], key: str, where: str, *, required: bool, positive: bool = ...,
            nonnegative: bool = ..., lo: float | None = ..., hi: float | None = ...,
            default: float) -> float: ...
@overload
def _number(sec: dict[str, Any], key: str, where: str, *, required: bool, positive: bool = ...,
            nonnegative: bool = ..., lo: float | None = ..., hi: float | None = ...,
            default: None = ...) -> float | None: ...
def _number(sec: dict[str, Any], key: str, where: str, *, required: bool = True,
            positive: bool = True, nonnegative: bool = False, lo: float | None = None,
            hi: float | None = None, default: float | None = None) -> float | None:
    """A finite number ``sec[key]`` within the checks, or ``default`` when absent and not ``required``."""
    if key not in sec or sec[key] is None:
        if required:
            raise ParamError(f"{where}: missing key '{key}'")
        return default
    value = sec[key]
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ParamError(f"{where}.{key}: expected a number, got {value!r}")
    try:
        number = float(value)
    except ValueError:
        raise ParamError(f"{where}.{key}: expected a number, got {value!r}") from None
    if not math.isfinite(number):
        raise ParamError(f"{where}.{key}: must be finite, got {value!r}")
    if positive and number <= 0.0:
        raise ParamError(f"{where}.{key}: must be > 0, got {number:g}")
    if nonnegative and number < 0.0:
        raise ParamError(f"{where}.{key}: must be >= 0, got {number:g}")
    if lo is not None and number <= lo:
        raise ParamError(f"{where}.{key}: must be > {lo:g}, got {number:g}")
    if hi is not None and number > hi:
        raise ParamError(f"{where}.{key}: must be <= {hi:g}, got {number:g}")
    return number


_T = TypeVar("_T", bound="DataclassInstance")
_AT_LEAST_ZERO = {"positive": False, "nonnegative": True}


def _build(cls: type[_T], sec: dict[str, Any], where: str, rules: dict[str, dict[str, Any]]) -> _T:
    """Build dataclass ``cls`` from ``sec`` taking numeric fields through :func:`_number`."""
    kwargs: dict[str, float | None] = {}
    for f in fields(cls):
        if f.name in rules:
            kwargs[f.name] = _number(sec, f.name, where, **rules[f.name])
    return cls(**kwargs)


def _material(sec: dict[str, Any], where: str, raceway: bool) -> Material:
    return _build(Material, sec, where, {
        "elastic_modulus": {},
        "poisson_ratio": {"positive": False, "lo": -1.0, "hi": 0.5},
        "hardness": {"required": raceway},
        "yield_strength": {"required": raceway},
        "density": {"required": False, "default": 7850.0},
    })


def unit_from_dict(data: Any, where: str = "unit", blocks: tuple[str, ...] | None = None) -> UnitParams:
    """Validate a parsed unit mapping; ``where`` names it in error messages.

    ``blocks``: the blocks to read, each required (``monitor`` stays optional); None = the wear
    model's blocks (:data:`WEAR_BLOCKS`) required, ``actuator`` and ``monitor`` read when present.
    Blocks not read are neither validated nor available (:class:`MissingBlock`).
    """
    if not isinstance(data, dict):
        raise ParamError(f"{where}: expected a mapping at the top level")
    unknown = set(blocks or ()) - set(BLOCKS)
    if unknown:
        raise ValueError(f"unknown unit-file block(s) {sorted(unknown)}; known: {', '.join(BLOCKS)}")
    if blocks is None:
        wanted = set(WEAR_BLOCKS) | ({"actuator"} if data.get("actuator") is not None else set())
    else:
        wanted = set(blocks) | {"ball_screw"}
    bs = _section(data, "ball_screw", where)
    w = f"{where}: ball_screw"
    ball_screw = _build(BallScrew, bs, w, {
        "ball_radius": {}, "pitch_diameter": {}, "lead": {},
        "screw_conformity": {"lo": 0.5}, "nut_conformity": {"lo": 0.5},
        "contact_angle_deg": {"hi": 90.0},
        "helix_angle_deg": {"required": False, "hi": 45.0},
        "dynamic_load_rating": {"required": False},
        "effective_balls": {},
    })
    if float(ball_screw.effective_balls) != int(ball_screw.effective_balls):
        raise ParamError(f"{w}.effective_balls: must be a whole number, got {ball_screw.effective_balls:g}")
    ball_screw = BallScrew(**(asdict(ball_screw) | {"effective_balls": int(ball_screw.effective_balls)}))
    if ball_screw.pitch_diameter <= 2.0 * ball_screw.ball_radius:
        raise ParamError(f"{w}.pitch_diameter: must exceed the ball diameter 2 r_b")

    materials: Materials | MissingBlock = MissingBlock("materials", where)
    lubricant: Lubricant | MissingBlock = MissingBlock("lubricant", where)
    wear: WearParams | MissingBlock = MissingBlock("wear", where)
    if "materials" in wanted:
        materials = _materials(data, where)
    if "lubricant" in wanted:
        lubricant = _build(Lubricant, _section(data, "lubricant", where), f"{where}: lubricant",
                           {"viscosity": {}, "pressure_viscosity": {}})
    if "wear" in wanted:
        wear = _build(WearParams, _section(data, "wear", where), f"{where}: wear", {
            "k_slip": {}, "raceway_share": {"hi": 1.0},
            "boundary_friction": _AT_LEAST_ZERO | {"hi": MAX_BOUNDARY_FRICTION},
        })
    actuator = _actuator(_section(data, "actuator", where), f"{where}: actuator") \
        if "actuator" in wanted else None

    mon = data.get("monitor") or {}
    if not isinstance(mon, dict):
        raise ParamError(f"{where}: section 'monitor' must be a mapping")
    monitor = _build(MonitorParams, mon, f"{where}: monitor",
                     {k: {"required": False, "positive": False, "nonnegative": True,
                          "default": getattr(MonitorParams, k)} for k in ("warn_cycles", "due_cycles")}
                     | {"clearance_limit": {"required": False, "default": MonitorParams.clearance_limit}})
    if actuator is not None and monitor.clearance_limit <= actuator.clearance:
        raise ParamError(f"{where}: monitor.clearance_limit must exceed actuator.clearance")
    if monitor.due_cycles > monitor.warn_cycles:
        raise ParamError(f"{where}: monitor.due_cycles must not exceed monitor.warn_cycles")
    name = str(data.get("name", Path(where).stem))
    return UnitParams(ball_screw, materials, lubricant, wear, actuator, monitor, name, data)


def _materials(data: dict[str, Any], where: str) -> Materials:
    mats = _section(data, "materials", where)
    return Materials(
        ball=_material(_section(mats, "ball", f"{where}: materials"), f"{where}: materials.ball", False),
        screw=_material(_section(mats, "screw", f"{where}: materials"), f"{where}: materials.screw", True),
        nut=_material(_section(mats, "nut", f"{where}: materials"), f"{where}: materials.nut", True),
        composite_roughness=_number(mats, "composite_roughness", f"{where}: materials"),
        asperity_radius=_number(mats, "asperity_radius", f"{where}: materials", required=False),
    )


def _actuator(act: dict[str, Any], wa: str) -> Actuator:
    return Actuator(
        motor=_build(Motor, _section(act, "motor", wa), f"{wa}.motor", {
            "torque_constant": {}, "back_emf_constant": {}, "resistance": {},
            "inductance": {}, "inertia": {},
            "continuous_stall_torque": {"required": False, "default": Motor.continuous_stall_torque}}),
        friction=_build(Friction, _section(act, "friction", wa), f"{wa}.friction", {
            "static": _AT_LEAST_ZERO, "coulomb": _AT_LEAST_ZERO, "viscous": _AT_LEAST_ZERO,
            "load_coefficient": _AT_LEAST_ZERO}),
        **{k: _number(act, k, wa) for k in (
            "gear_ratio", "screw_inertia", "gear_inertia", "nut_mass", "clearance", "stiffness")},
        **{k: _number(act, k, wa, required=False, default=getattr(Actuator, k))
           for k in ("supply_voltage", "current_limit")},
    )


def reference_path(name: str = "embu_000") -> Path:
    """Path of a shipped reference unit file: ``embu_000`` (paper 000) or ``screw_003`` (paper 003)."""
    if name not in REFERENCE_UNITS:
        raise ParamError(f"unknown reference unit '{name}' (known: {', '.join(REFERENCE_UNITS)})")
    return Path(str(resources.files(__package__) / "reference" / REFERENCE_UNITS[name]))


def load_unit(path: str | Path | None = None, blocks: tuple[str, ...] | None = None) -> UnitParams:
    """Load and validate a unit YAML file (default: the reference EMBU of paper 000).

    ``path`` may also be a reference name (``embu_000``, ``screw_003``). ``blocks``: the blocks
    the caller uses (:func:`unit_from_dict`; e.g. :data:`CONTACT_BLOCKS`), None = the wear model's.
    Raises :class:`ParamError` (one line) for unreadable, malformed or invalid files.
    """
    if path is None:
        path = reference_path()
    elif str(path) in REFERENCE_UNITS:
        path = reference_path(str(path))
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ParamError(f"{path}: cannot read unit file ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise ParamError(f"{path}: not a UTF-8 text file") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        at = f" at line {mark.line + 1}" if mark is not None else ""
        raise ParamError(f"{path}: malformed YAML{at}") from None
    return unit_from_dict(data, str(path), blocks)


def accelerated(unit: UnitParams, wear_scale: float) -> UnitParams:
    """``unit`` on an accelerated-life rig: Archard's k_slip (000 eq. 20) multiplied by ``wear_scale`` [-].

    A monitor replaying such a rig's recordings must use the same file, or its wear
    model under-predicts the growth by ``wear_scale``.
    """
    if not (math.isfinite(wear_scale) and wear_scale > 0.0):
        raise ParamError(f"wear scale must be a finite number > 0, got {wear_scale!r}")
    raw = copy.deepcopy(unit.raw)
    raw["wear"]["k_slip"] = float(raw["wear"]["k_slip"]) * wear_scale
    raw["name"] = f"{unit.name}, wear x{wear_scale:g}"
    return unit_from_dict(raw, f"{unit.name} (accelerated)")


def save_unit(path: str | Path, unit: UnitParams, header: str = "") -> Path:
    """Write ``unit`` as a unit YAML file (atomically), ``header`` as leading comment lines."""
    from ebm_wear_monitor.outputs import atomic_write

    comment = "".join(f"# {line}\n" for line in header.splitlines())
    text = comment + yaml.safe_dump(unit.raw, sort_keys=False)
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))

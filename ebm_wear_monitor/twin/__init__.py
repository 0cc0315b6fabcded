"""Digital twin of the EMB actuator (paper 004) with its brake controller and the wear coupling (000).

Public API::

    actuator_torques(unit, clamp_force_N) -> ActuatorResult      # calc actuator (interface.md section 4)
    simulate_unit(unit, cycles, demands=None, effects={name: magnitude}, seed=0, rate_hz=1000,
                  wear_acceleration=1.0, *, hold_s=1.0, rest_s=0.5, ...) -> SimResult
    simulate_current_driven(unit | ActuatorModel, t, current, x0=(angle, velocity)) -> Trajectory
    simulate_voltage_driven(unit | ActuatorModel, t, voltage, x0=None) -> Trajectory
    actuator_model(unit) -> ActuatorModel; apply_effects(model, effects) -> ActuatorModel
    CATALOG, SensorNoise, NOISELESS, BrakeController   (phases: ebm_wear_monitor.domain.phases)

Modules: :mod:`.friction` (004 eq. 9), :mod:`.clamp` (eq. 5-6), :mod:`.dynamics`
(eq. 1-8, integrator), :mod:`.holding` (eq. 1, 9, 42: calc actuator), :mod:`.controller` (four
phases of 000 Fig. 2), :mod:`.effects` (catalog), :mod:`.sensors` (noise), :mod:`.simulator`
(duty cycles + wear). 004's own actuator, its component friction (eq. 18-41) and the closed forms
of its figures (eq. 10-17, 43) reproduce the paper: :mod:`ebm_wear_monitor.validation.papers`.
"""

from ebm_wear_monitor.twin.controller import BrakeController
from ebm_wear_monitor.twin.dynamics import (
    ActuatorModel,
    Trajectory,
    actuator_model,
    simulate_current_driven,
    simulate_voltage_driven,
)
from ebm_wear_monitor.twin.effects import CATALOG, apply_effects
from ebm_wear_monitor.twin.friction import FrictionLaw
from ebm_wear_monitor.twin.holding import actuator_torques
from ebm_wear_monitor.twin.sensors import NOISELESS, SensorNoise
from ebm_wear_monitor.twin.simulator import DEFAULT_DEMANDS, SimResult, simulate_unit

__all__ = [
    "CATALOG",
    "DEFAULT_DEMANDS",
    "NOISELESS",
    "ActuatorModel",
    "BrakeController",
    "FrictionLaw",
    "SensorNoise",
    "SimResult",
    "Trajectory",
    "actuator_model",
    "actuator_torques",
    "apply_effects",
    "simulate_current_driven",
    "simulate_unit",
    "simulate_voltage_driven",
]

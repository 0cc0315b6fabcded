"""Unit parameter files (interface.md section 3): loading, validation, reference designs."""

from ebm_wear_monitor.params.unit import (
    Actuator,
    BallScrew,
    Friction,
    Lubricant,
    Material,
    Materials,
    MonitorParams,
    Motor,
    ParamError,
    UnitParams,
    WearParams,
    accelerated,
    load_unit,
    reference_path,
    save_unit,
    unit_from_dict,
)

__all__ = [
    "Actuator",
    "BallScrew",
    "Friction",
    "Lubricant",
    "Material",
    "Materials",
    "MonitorParams",
    "Motor",
    "ParamError",
    "UnitParams",
    "WearParams",
    "accelerated",
    "load_unit",
    "reference_path",
    "save_unit",
    "unit_from_dict",
]

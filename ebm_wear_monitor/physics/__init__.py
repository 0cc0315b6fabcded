"""Ball-screw contact and Archard wear core of papers 000 and 003 (pure numpy, no ROS).

Public API:

* :func:`wear_model` / :class:`WearModel` / :class:`WearRates`: wear-depth rates of
  screw raceway, nut raceway and ball for arrays of axial force and screw speed;
* :func:`clearance_growth`: axial clearance growth from wear depths;
* :func:`contact_report` and :func:`wear_report`: the results of ``ebm-wear calc contact`` and
  ``ebm-wear calc wear`` (records of :mod:`ebm_wear_monitor.schema.calc`; interface.md section 4);
* :class:`ModelOptions`: the selectable readings of 000's ambiguous equations.
"""

from ebm_wear_monitor.physics.archard import clearance_growth
from ebm_wear_monitor.physics.model import METHODS, WearModel, WearRates, wear_model
from ebm_wear_monitor.physics.options import ModelOptions
from ebm_wear_monitor.physics.reports import contact_report, wear_report
from ebm_wear_monitor.physics.surrogate import ENVELOPE, Envelope

__all__ = [
    "ENVELOPE",
    "METHODS",
    "Envelope",
    "ModelOptions",
    "WearModel",
    "WearRates",
    "clearance_growth",
    "contact_report",
    "wear_model",
    "wear_report",
]

"""The foreign world: an independent recording generator for validating the project.

Written without the project's twin, diagnosis, monitor, physics, bag or replay code (it imports
nothing from ``ebm_wear_monitor`` outside this package; a test checks that): its own plant
integration of paper 004, its own brake ECUs, its own sensors and acquisition conventions, bags
written with rosbags directly. Everything it does is documented in ``README.md`` beside this file.

    from ebm_wear_monitor.validation.foreign import Case, case_set, write_case
    cases = case_set("quick")                 # deterministic, seeded
    bag_dir = write_case(cases[0], out_dir)   # rosbag2 directory with ground_truth.json

    python -m ebm_wear_monitor.validation.foreign write --set quick --out DIR [--jobs N]
"""

from .cases import Case, case_set
from .recording import write_case

__all__ = ["Case", "case_set", "write_case"]

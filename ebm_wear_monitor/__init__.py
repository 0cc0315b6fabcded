"""ebm_wear_monitor: ball-screw wear monitor for railway electro-mechanical brake units."""

__version__ = "0.1.0"

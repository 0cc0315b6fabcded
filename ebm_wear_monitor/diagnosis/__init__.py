"""Sim-to-real gap diagnosis: where the twin of 004 misses, which unmodelled effect explains it, how far.

Public API::

    from ebm_wear_monitor.diagnosis import diagnose_recording, recording_from_signals, Resampled
    result = diagnose_recording(recording, unit)   # schema.diagnose.DiagnosisResult, interface.md section 4
    result.verdict, result.ranking[0].magnitude, result.to_json_dict()

Modules: :mod:`.recording` (signals on one time base), :mod:`.phases` (phase and
cycle labels), :mod:`.noise` (measured noise), :mod:`.residuals` (re-anchored
torque and force residuals), :mod:`.catalog` (effects), :mod:`.ranking`
(held-out fit, ranking, verdict), :mod:`.where`, :mod:`.pipeline`.
"""

from ebm_wear_monitor.diagnosis.pipeline import diagnose_recording
from ebm_wear_monitor.diagnosis.recording import Resampled, recording_from_signals

__all__ = ["Resampled", "diagnose_recording", "recording_from_signals"]

"""Reproductions of the papers' tables and figures, and nothing else (issue 14 item 3).

:mod:`.paper000`: the reconstructed duty cycle of 000 Fig. 5, its per-cycle wear (Table 3) and
000's own gap between model and endurance test worked out. :mod:`.paper004`: 004's actuator
(Tables 1, 3, 4) and the closed forms of its figures (eq. 10-17, 43); :mod:`.paper004_components`:
its component friction (eq. 18-41) summed to Table 3. Runtime modules (node, replay, fleet,
diagnose, simulate, calc) never import this package; the tests and benchmarks do.
"""

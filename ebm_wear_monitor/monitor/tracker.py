"""Outliers, steps of the clearance and changes of its growth rate, around the filter bank (kalman.py).

A sustained trend must never be mistaken for outliers, and a step of the
clearance (an adjustment, maintenance, a fracture) must not be read as growth.
Three mechanisms, all on the innovations y_k = z_k - c_k of the bank:

1. **Gate.** An observation whose innovation exceeds ``innovation_gate_sigma``
   standard deviations sqrt(S) in *every* component is not fused (counted
   ``observation_rejected``). One such observation is an outlier. Because every
   component, including those that have learned a fast or accelerating growth,
   must reject it, a trend the bank can follow is never gated.
2. **Run of gated observations = a large step.** ``reset_after_rejections``
   gated observations in a row on the same side mean the clearance itself moved
   by more than the gate: the step is placed at the first of them (see 4).
3. **Generalised likelihood ratio (GLR) for small steps and rate changes**
   (Willsky and Jones, IEEE Trans. Autom. Control 21 (1976) 108-112). A jump
   nu = [nu_c, nu_r] of the clearance and/or of the growth rate just before
   application j, unknown to the filter, shifts every later innovation by a
   known linear signature: with mu_j = [e_c, e_r] (3 x 2) at j and, per
   application k >= j,

       G_k = H mu_k,   mu_k <- (I - K_k H) mu_k (after the update),   mu_k+1 = F_k+1 mu_k,

   the innovations are y_k = G_k nu + white noise of variance S_k, so the
   maximum-likelihood jump and its log-likelihood ratio (times 2) are

       d_j = sum_k G_k' y_k / S_k,  C_j = sum_k G_k' G_k / S_k,  nu_j = C_j^-1 d_j,  T_j = d_j' C_j^-1 d_j.

   T is chi-square with 1 (clearance or rate alone) or 2 degrees of freedom
   (both) under "no jump". Over the ``change_window_cycles`` = W candidate
   applications j the thresholds are h_dof = chi2.isf(alpha / W, dof) with
   alpha = ``change_false_alarm_per_cycle`` (Bonferroni: at most alpha false
   detections per application). All T are likelihood ratios on the same data,
   so the explanations are compared directly, with the best j of each:

   * a **step** when T_step > h_1, T_step >= T_change and T_both - T_step < h_1
     (a rate change on top adds nothing significant);
   * a **rate change** when T_change > h_1 and T_change >= T_step + h_1: a
     ramp is fitted partly by a step (3/4 of its sum of squares), so a change
     must beat every step decisively, and a ramp is never eaten as a staircase;
   * **both** when T_both > h_2 and it beats the better single one by h_1.

   It is acted on once the chosen candidate has :data:`MIN_STEP_OBSERVATIONS`
   (step) or :data:`MIN_CHANGE_OBSERVATIONS` (rate change) fused observations;
   otherwise the decision waits. The statistic is that of the leading
   component (largest weight).
4. **Re-filtering.** A detected jump is not patched onto the estimate: the bank
   is re-run from its copy W applications back (the *anchor*) over the stored
   observations, with the prior variance of the clearance and/or the rate
   (``initial_clearance_std_m``, sigma_r0 and ``initial_factor_std``) added at j.
   Each component then estimates the jump it needs from the data after j
   (Bayes-optimal for a diffuse jump) and its weight is judged fairly on them.

The live bank is therefore always ``replay(anchor, records)``: the anchor bank
and the last W records (model growth, observation, its error budget, jump
flags), the whole persistent state. Replaying it gives bit-identical numbers,
so a restarted monitor continues exactly where it stopped. The tracker keeps the
live bank as it was after each record (``replay(anchor, records[:j + 1])``,
rebuilt with it): when the oldest record leaves the window, the one after it is
the new anchor, the same numbers as filtering the anchor with that record again,
without filtering it a second time.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.special import ndtri

from ebm_wear_monitor.monitor.config import MonitorConfig
from ebm_wear_monitor.monitor.kalman import DIM, Bank, Hypotheses, one_blas_thread

#: fused observations a clearance step needs after it before it is acted on (a gated observation alone
#: is an outlier; a step confirmed by three consecutive ones is not)
MIN_STEP_OBSERVATIONS = 3
#: ... a change of the growth rate: its signature grows as 1, 2, 3, ... observations after the change and
#: is told from a step's constant offset only over several applications
MIN_CHANGE_OBSERVATIONS = 10

FUSED, REJECTED, NONE = "fused", "rejected", "none"
_NO_Y = np.zeros(0)


@functools.lru_cache(maxsize=8)
def _thresholds(alpha: float, window: int) -> tuple[float, float]:
    """GLR thresholds h_1, h_2: chi-square quantiles at alpha / W (module docstring, item 3), in closed
    form: chi2_1 = z^2 with z the normal quantile at alpha / 2W; chi2_2 is exponential, -2 ln(alpha / W)."""
    p = alpha / window
    return float(ndtri(0.5 * p) ** 2), -2.0 * math.log(p)


@dataclass
class Record:
    """One application as the tracker saw it. SI units."""

    growth_m: float  # the wear model's clearance growth of the application [m]
    observed_m: float  # observed clearance [m], NaN when not observable
    budget_var_m2: float  # its error budget R [m^2], NaN when not observable
    step: bool = False  # the clearance may jump before this observation
    change: bool = False  # the growth rate may jump before this observation

    def to_list(self) -> list[float | bool | None]:
        z, r = (None if math.isnan(v) else v for v in (self.observed_m, self.budget_var_m2))
        return [self.growth_m, z, r, self.step, self.change]

    @classmethod
    def from_list(cls, item: Any) -> Record:
        g, z, r, step, change = item
        z = math.nan if z is None else float(z)
        r = math.nan if r is None else float(r)
        if not (math.isfinite(float(g)) and (math.isnan(z) == math.isnan(r))
                and (math.isnan(r) or r > 0.0) and isinstance(step, bool) and isinstance(change, bool)):
            raise ValueError(f"malformed tracker record {item!r}")
        return cls(float(g), z, r, step, change)


@dataclass
class _Signatures:
    """GLR sums per component and candidate application (module docstring, item 3)."""

    mu: np.ndarray  # (M, n, 3, 2)
    d: np.ndarray  # (M, n, 2)
    C: np.ndarray  # (M, n, 2, 2)
    fused: np.ndarray  # (n,) fused observations since each candidate

    @classmethod
    def empty(cls, m: int) -> _Signatures:
        return cls(np.zeros((m, 0, DIM, 2)), np.zeros((m, 0, 2)), np.zeros((m, 0, 2, 2)), np.zeros(0, int))

    def open_candidate(self) -> None:
        m = self.mu.shape[0]
        mu = np.zeros((m, 1, DIM, 2))
        mu[:, 0, 0, 0] = mu[:, 0, 1, 1] = 1.0
        self.mu = np.concatenate([self.mu, mu], axis=1)
        self.d = np.concatenate([self.d, np.zeros((m, 1, 2))], axis=1)
        self.C = np.concatenate([self.C, np.zeros((m, 1, 2, 2))], axis=1)
        self.fused = np.append(self.fused, 0)

    def drop_oldest(self) -> None:
        self.mu, self.d, self.C, self.fused = self.mu[:, 1:], self.d[:, 1:], self.C[:, 1:], self.fused[1:]


@dataclass
class StepResult:
    """What one application did: ``outcome`` in {fused, rejected, none}; jumps detected (counts)."""

    outcome: str
    steps: int = 0
    changes: int = 0


@dataclass
class ClearanceTracker:
    """The filter bank with its change detection. Build with :meth:`start` or :meth:`from_dict`."""

    hyp: Hypotheses
    config: MonitorConfig
    rate_std_m: float  # sigma_r0 of kalman.py [m]
    anchor: Bank  # the bank before the oldest record
    records: list[Record] = field(default_factory=list)
    live: Bank = field(init=False)
    _sig: _Signatures = field(init=False)
    _signs: list[float] = field(init=False)  # sign of the leading innovation of each record (0: fused/none)
    _after: list[Bank] = field(init=False)  # the live bank after each record: replay(anchor, records[:j + 1])

    def __post_init__(self) -> None:
        with one_blas_thread():
            self._rebuild()

    @classmethod
    def start(cls, config: MonitorConfig, clearance_m: float, clearance_var_m2: float, limit_m: float,
              **factor: float) -> ClearanceTracker:
        """A new tracker at the clearance prior; ``factor``: optional model-factor prior
        (``factor``, ``factor_var``, ``clearance_factor_cov``) carried over from an issue-5 filter."""
        hyp = Hypotheses.build(config)
        rate_std = max(limit_m - clearance_m, 1e-6) / config.min_cycles_for_life
        return cls(hyp, config, rate_std, Bank.prior(hyp, config, clearance_m, clearance_var_m2, rate_std,
                                                     **factor))

    def configure(self, config: MonitorConfig) -> None:
        """New thresholds from the next application on (prior weights only matter at the start)."""
        self.config, self.hyp = config, Hypotheses.build(config)
        with one_blas_thread():
            while len(self.records) > config.change_window_cycles:
                self._filter(self.anchor, self.records.pop(0))
            self._rebuild()

    # ---------------------------------------------------------------- one application
    def _filter(self, bank: Bank, rec: Record) -> tuple[np.ndarray, np.ndarray | None, np.ndarray, np.ndarray,
                                                         float, str]:
        """Predict (opening a flagged jump), then update unless gated.

        Returns (F, K or None, y, S, sign of the leading innovation when gated else 0, outcome).
        """
        cfg = self.config
        F = bank.predict(self.hyp, cfg, rec.growth_m)
        if rec.step or rec.change:
            bank.open(self.hyp, cfg.initial_clearance_std_m ** 2 if rec.step else 0.0,
                      self.rate_std_m ** 2 if rec.change else 0.0,
                      cfg.initial_factor_std ** 2 if rec.change else 0.0)
        if math.isnan(rec.observed_m):
            return F, None, _NO_Y, _NO_Y, 0.0, NONE
        y, S = bank.innovation(rec.observed_m, rec.budget_var_m2)
        if np.all(np.abs(y) > cfg.innovation_gate_sigma * np.sqrt(S)):
            return F, None, y, S, float(np.sign(y[int(np.argmax(bank.logw))])), REJECTED
        return F, bank.update(cfg, rec.observed_m, rec.budget_var_m2, y, S), y, S, 0.0, FUSED

    def _apply(self, bank: Bank, rec: Record) -> str:
        """:meth:`_filter` plus the GLR sums of every candidate in the window (item 3)."""
        sig = self._sig
        sig.open_candidate()
        F, K, y, S, sign, outcome = self._filter(bank, rec)
        sig.mu[:, :-1] = F[:, None] @ sig.mu[:, :-1]  # mu <- F mu for every candidate
        self._signs.append(sign)
        if K is not None:
            G = sig.mu[:, :, 0, :]  # (M, n, 2): H mu
            sig.d += G * (y / S)[:, None, None]
            sig.C += G[..., :, None] * G[..., None, :] / S[:, None, None, None]
            sig.mu -= K[:, None, :, None] * G[:, :, None, :]
            sig.fused += 1
        return outcome

    def _advance(self, rec: Record) -> str:
        """:meth:`_apply` to the live bank, which is then kept as the bank after ``rec``."""
        outcome = self._apply(self.live, rec)
        self._after.append(self.live.copy())
        return outcome

    def _rebuild(self) -> None:
        """live = replay(anchor, records), with the GLR sums and the bank after each record (item 4)."""
        self.live = self.anchor.copy()
        self._sig = _Signatures.empty(self.hyp.size)
        self._signs, self._after = [], []
        for rec in self.records:
            self._advance(rec)

    def step(self, growth_m: float, observed_m: float, budget_var_m2: float) -> StepResult:
        """One brake application: model growth [m], observed clearance [m] (NaN: none), its budget R [m^2]."""
        rec = Record(float(growth_m), float(observed_m), float(budget_var_m2))
        if math.isnan(rec.observed_m) or not rec.budget_var_m2 > 0.0:
            rec.observed_m = rec.budget_var_m2 = math.nan
        self.records.append(rec)
        with one_blas_thread():
            result = StepResult(self._advance(rec))
            if result.outcome == REJECTED:
                self._large_step(result)
            elif result.outcome == FUSED:
                self._detect(result)
        if len(self.records) > self.config.change_window_cycles:
            self.records.pop(0)
            self.anchor = self._after.pop(0)  # = the anchor filtered with the record that left
            self._sig.drop_oldest()
            self._signs.pop(0)
        return result

    def _large_step(self, result: StepResult) -> None:
        """Item 2: the last ``reset_after_rejections`` observations all gated, on one side."""
        n = self.config.reset_after_rejections
        observed = [i for i, r in enumerate(self.records) if not math.isnan(r.observed_m)][-n:]
        signs = {self._signs[i] for i in observed}
        if len(observed) == n and len(signs) == 1 and 0.0 not in signs:
            self.records[observed[0]].step = True
            result.steps += 1
            self._rebuild()

    def _detect(self, result: StepResult) -> None:
        """Item 3: GLR of the leading component over the window; act on the best explained jump."""
        sig, lead = self._sig, int(np.argmax(self.live.logw))
        d, C, fused = sig.d[lead], sig.C[lead], sig.fused
        with np.errstate(divide="ignore", invalid="ignore"):
            t_step = np.where(fused >= 1, d[:, 0] ** 2 / C[:, 0, 0], 0.0)
            t_change = np.where(fused >= 2, d[:, 1] ** 2 / C[:, 1, 1], 0.0)
            det = C[:, 0, 0] * C[:, 1, 1] - C[:, 0, 1] ** 2
            both = (C[:, 1, 1] * d[:, 0] ** 2 - 2.0 * C[:, 0, 1] * d[:, 0] * d[:, 1]
                    + C[:, 0, 0] * d[:, 1] ** 2) / det
            t_both = np.where((fused >= 2) & (det > 1e-9 * C[:, 0, 0] * C[:, 1, 1]), both, 0.0)
        h1, h2 = _thresholds(self.config.change_false_alarm_per_cycle, self.config.change_window_cycles)
        t_step, t_change, t_both = (np.nan_to_num(t) for t in (t_step, t_change, t_both))
        best = {kind: (float(np.max(t)), int(np.argmax(t)))
                for kind, t in (("step", t_step), ("change", t_change), ("both", t_both))}
        ts, tc, tb = best["step"][0], best["change"][0], best["both"][0]
        if ts > h1 and ts >= tc and tb - ts < h1:
            kind = "step"  # a step, and neither a rate change nor a rate change on top explains it better
        elif tc > h1 and tc >= ts + h1 and tb - tc < h1:
            kind = "change"  # a rate change, decisively better than any step (a ramp is not a staircase)
        elif tb > h2 and tb - max(ts, tc) > h1:
            kind = "both"
        else:
            return
        j = best[kind][1]
        if fused[j] < (MIN_STEP_OBSERVATIONS if kind == "step" else MIN_CHANGE_OBSERVATIONS):
            return  # the best explanation needs more observations: wait
        rec = self.records[j]  # candidate j counts from the oldest record in the window
        rec.step = rec.step or kind in ("step", "both")
        rec.change = rec.change or kind in ("change", "both")
        result.steps += kind in ("step", "both")
        result.changes += kind in ("change", "both")
        self._rebuild()

    # ---------------------------------------------------------------- persistence
    def to_dict(self) -> dict[str, Any]:
        return {"anchor": self.anchor.to_dict(), "records": [r.to_list() for r in self.records]}

    @classmethod
    def from_dict(cls, data: dict[str, Any], config: MonitorConfig, clearance_m: float,
                  limit_m: float) -> ClearanceTracker:
        """Inverse of :meth:`to_dict` (``clearance_m``: the nominal clearance the tracker started from)."""
        hyp = Hypotheses.build(config)
        rate_std = max(limit_m - clearance_m, 1e-6) / config.min_cycles_for_life
        records = [Record.from_list(r) for r in data["records"]]
        return cls(hyp, config, rate_std, Bank.from_dict(data["anchor"], hyp.size), records)

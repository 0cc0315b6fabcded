"""The axial clearance and its growth rate, learned from the observations: a bank of Kalman filters.

The wear model (000 eq. 20-23 through ``physics.clearance_growth``) predicts the
clearance growth g_k of each brake application k. It may be right, a little off,
or wrong by orders of magnitude (a textbook wear coefficient, a lubrication
failure, contamination, another material). The monitor must follow the measured
clearance whatever the model says, and still use the model where the data cannot
tell yet. So the growth is a *hypothesis test* between a small set of linear
state-space models, each a Kalman filter, run side by side on the same
observations (a Gaussian-sum or multiple-model filter; Bar-Shalom, Li and
Kirubarajan, *Estimation with Applications to Tracking and Navigation*, ch. 11).

State and transition
--------------------
Every component i has the state x = [c, r, a]: c the axial clearance [m], r the
clearance growth per application beyond the model's [m], a the change of r per
application [m] (used by one family only). Between applications k-1 and k::

    c_k = c_k-1 + g_k + r_k-1 + a_k-1 / 2          r_k = rho_i r_k-1 + a_k-1          a_k = a_k-1

i.e. x_k = F_i x_k-1 + B g_k with F_i = [[1, 1, 1/2], [0, rho_i, 1], [0, 0, 1]]
(the a-terms only for the accelerating component) and B = [1, 0, 0]'. The
components differ in their dynamics and their prior:

* **model** (the wear model is right up to a factor): x = [c, f, 0],
  c_k = c_k-1 + f g_k, f ~ N(1, s_f^2) with s_f = ``initial_factor_std``, as the
  filter of issue 5. F = [[1, g_k, 0], [0, 1, 0], [0, 0, 1]], no B.
* **steady** (rho = 1): the growth per application is g_k + r with r constant,
  r ~ N(0, sigma_r0^2).
* **accelerating, exponential** (rho = 1 + lambda, lambda on a log grid of
  :data:`E_FOLDING_RATES` from 1e-4 to 3e-2 per application: the extra growth
  rate e-folds in 10,000 to 33 applications): wear that feeds itself (a larger
  clearance hits harder, debris abrades).
* **accelerating, constant** (rho = 1, a ~ N(0, sigma_a0^2)): a rate that climbs
  linearly, e.g. a lubricant that degrades steadily.

Each data-driven dynamics comes twice: with a steady rate and with a rate that
wanders by ``rate_wander_per_cycle`` of itself per application (model error of
the dynamics; lets exponential and constant-acceleration histories that fall
between the grid points be followed).

Process noise: Q_k = diag((s_g g_k)^2, q_r^2, 0) with s_g = ``growth_scatter``
(cycle-to-cycle spread of the model's growth) and q_r = ``factor_drift_per_cycle``
for the model component, ``rate_wander_per_cycle`` * |r| for the wandering ones,
0 otherwise.

Priors (why the model is informative but never a constraint)
------------------------------------------------------------
The data-driven components start at r ~ N(0, sigma_r0^2) with sigma_r0 =
(L - x_nom) / N_min, L the clearance limit, x_nom the nominal clearance and
N_min = ``min_cycles_for_life``: the fastest growth that matters consumes the
whole margin before the first remaining life can be issued. Any rate from 0 to
~10^6 x the model (3e-5 m per application for the reference EMBU) lies within
about one sigma_r0: the prior never holds a rate back. The model enters twice:
as the prior *mean* of the growth (the input g_k of every component) and as the
model component, whose prior weight ``model_prior_weight`` (1/2: no preference)
is its informative part. Component weights w_i follow Bayes' rule with the
innovation likelihood of each filter::

    w_i <- w_i N(y_i; 0, S_i) / sum_j w_j N(y_j; 0, S_j),     S_i = P_i,cc + R,

then w <- (1 - eps) w + eps / M (eps = ``regime_change_per_cycle``: the unit may
change its wear regime, so no hypothesis is ever ruled out for good).

Learning time is set by the observation noise, not by the prior. After N
applications of observation noise sigma, a steady component knows r to
sigma_r = sigma sqrt(12 / N^3) (least squares on a line; the prior's information
1 / sigma_r0^2 is negligible after two observations). Against the model
component, whose growth is g (1 +- s_f), its weight ratio grows as

    ln(w_steady / w_model) = z^2 / 2 - ln(sigma_r0 / sigma_r) + ln(prior odds),    z = (r - g) / sigma_r

so it takes over once the accumulated growth departs from the model's by
z ~ 4-5 standard errors; z grows as N^(3/2), so that happens at
N ~ (12 (4.5 sigma / r)^2)^(1/3) applications, whatever the ratio of r to the
model's rate (0, 1e3 or 1e6 x g: tested). When the data agree with the model
(flat or model-like growth), the model keeps its weight (the Occam factor
sigma_r / sigma_r0 penalises the wider hypotheses), so a healthy unit's remaining
life comes from the model and is not shortened by noise.

Observation
-----------
z_k = c_k + v_k, H = [1, 0, 0], v_k ~ N(0, beta R_k) with R_k from the
observation's error budget (observation.py) and beta a noise scale estimated from
the data (the error budget is declared, its scale is measured): beta is the mean
over the observations of (y^2 - P_cc) / R_k (E[y^2] = P_cc + beta R_k), averaged
over the components that predicted the clearance better than one observation
measures it (P_cc < R_k) with their posterior weights, counted only when those
hold more than half the weight, and with ``noise_scale_prior_cycles``
pseudo-observations at beta = 1.

Update in Joseph form, per component: K = P H' / S, x += K y,
P = (I - K H) P (I - K H)' + K beta R K'.

One filter for the whole bank (block-diagonal stacking)
-------------------------------------------------------
The predict and the update are filterpy's (``filterpy.kalman.predict`` / ``update``, Labbe,
*Kalman and Bayesian Filters in Python*): x <- F x + B u, P <- F P F' (the process noise Q_k above
is added after it, since its rate term scales with the predicted r), and the Joseph-form update
with R = beta R_k. They run *once per step for all M components*: the components are independent
filters that observe the same z, so they are exactly one linear Kalman filter over the stacked
state X = [x_1; ...; x_M] (dimension 3M = 87) with

    F = blkdiag(F_1, ..., F_M),   B = [B_1; ...; B_M],   P = blkdiag(P_1, ..., P_M),
    H = blkdiag(H_1, ..., H_M) (M x 3M: row i picks c_i),   R = beta R_k I_M,   Z = [z, ..., z]'.

Why this is exact: a product or sum of block-diagonal matrices with the same blocks is
block-diagonal, block by block the product of the blocks. F P F' is, H P H' + R = diag(S_i) is
(so its inverse is diag(1 / S_i)), the gain P H' S^-1 is blkdiag(K_i), and the Joseph form
(I - K H) P (I - K H)' + K R K' is block i's Joseph form in block i. Every off-block entry is a sum
of products with an exact zero factor, hence exactly 0, and every in-block entry sums the same
non-zero terms as the component's own 3 x 3 filter: the stacked filter equals the M separate ones
up to the order of floating-point summation (~1e-16 relative). The innovations Y = Z - H X and
diag(S) are the components' own y_i and S_i; they give each component's likelihood for the
weights below (:meth:`Bank.innovation`). The bank stores the blocks, (M, 3) means and (M, 3, 3)
covariances (what the weights, the tracker and the remaining life read, and the persisted
layout), and stacks them for each filterpy call (:func:`block_diag`). The bank around filterpy
is ours: the hypotheses' F and B, the weights, the noise scale, the mixture. filterpy's package
import pulls scipy.stats (about 0.7 s), so it is imported on the first filter step
(:func:`load_filterpy`), not with this module: a tool that never filters does not pay for it,
and the node calls it before it subscribes. The stacked products (87 x 87 x 87) are just above the
size at which OpenBLAS splits a matrix product over threads, and a thread that waits for a busy core
costs far more than the product (a predict and update of the bank took 48 ms on two threads of a
shared two-core machine, 0.56 ms on one): the bank filters with BLAS on one thread
(:func:`one_blas_thread`, around each application of the tracker).

The clearance estimate reported is the mixture mean sum_i w_i c_i with the
mixture variance sum_i w_i (P_i,cc + (c_i - c)^2). Outliers, steps of the
clearance and changes of the growth rate are handled around this bank by
:mod:`.tracker`; remaining life from the mixture by :mod:`.life`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import numpy as np
from threadpoolctl import ThreadpoolController

from ebm_wear_monitor.monitor.config import MonitorConfig

#: e-folding rates lambda of the accelerating components [1/application] (rho = 1 + lambda)
E_FOLDING_RATES = np.geomspace(1e-4, 3e-2, 12)
_LOG_2PI = math.log(2.0 * math.pi)
DIM = 3  # [c, r, a]
#: components: the model, then (steady, each exponential, constant acceleration) x (steady, wandering rate)
COMPONENTS = 1 + 2 * (len(E_FOLDING_RATES) + 2)


def load_filterpy() -> ModuleType:
    """``filterpy.kalman``, imported on first use (its package import pulls scipy.stats)."""
    import filterpy.kalman

    module: ModuleType = filterpy.kalman
    return module


@functools.cache
def _blas_threads() -> ThreadpoolController:
    """The BLAS libraries loaded with numpy (found once: 1.4 ms; a limit on them costs 0.06 ms)."""
    return ThreadpoolController()  # type: ignore[no-untyped-call]  # (threadpoolctl: no annotations)


@contextmanager
def one_blas_thread() -> Iterator[None]:
    """BLAS on one thread inside the block: the bank's products are small (module docstring)."""
    with _blas_threads().limit(limits=1, user_api="blas"):
        yield


def block_diag(blocks: np.ndarray) -> np.ndarray:
    """The (M a, M b) block-diagonal matrix of M blocks (M, a, b): block i at rows a i.., columns b i.."""
    m, a, b = blocks.shape
    out = np.zeros((m, a, m, b))
    i = np.arange(m)
    out[i, :, i, :] = blocks
    return out.reshape(m * a, m * b)


def diagonal_blocks(stacked: np.ndarray, m: int) -> np.ndarray:
    """Inverse of :func:`block_diag` for square blocks: the M diagonal blocks (M, d, d) of (M d, M d)."""
    d = stacked.shape[0] // m
    i = np.arange(m)
    blocks: np.ndarray = stacked.reshape(m, d, m, d)[i, :, i, :]
    return blocks


@dataclass(frozen=True)
class Hypotheses:
    """The static structure of the bank: one entry per component (arrays of length M)."""

    rho: np.ndarray  # rate multiplier per application [-]
    accel: np.ndarray  # bool: constant-acceleration component (uses state a)
    wander: np.ndarray  # relative random walk of r per application [-]
    model: np.ndarray  # bool: the model-factor component (state [c, f, 0])
    log_prior: np.ndarray  # log prior weights (normalised)

    @classmethod
    def build(cls, config: MonitorConfig) -> Hypotheses:
        """Model component, then each data-driven dynamics with a steady and a wandering rate."""
        w_model, w_acc = config.model_prior_weight, config.accelerating_prior_weight
        w_steady = max(1.0 - w_model - w_acc, 0.0)
        dyn = [(1.0, False, w_steady)]
        n_acc = len(E_FOLDING_RATES) + 1
        dyn += [(1.0 + lam, False, w_acc / n_acc) for lam in E_FOLDING_RATES]
        dyn.append((1.0, True, w_acc / n_acc))
        rho, accel, wander, weight = [1.0], [False], [0.0], [w_model]
        for r, acc, w in dyn:
            for q in (0.0, config.rate_wander_per_cycle):
                rho.append(r)
                accel.append(acc)
                wander.append(q)
                weight.append(0.5 * w)
        weight_arr = np.asarray(weight)
        model = np.zeros(len(rho), bool)
        model[0] = True
        with np.errstate(divide="ignore"):
            log_prior = np.log(weight_arr / weight_arr.sum())
        return cls(np.asarray(rho), np.asarray(accel), np.asarray(wander), model, log_prior)

    @property
    def size(self) -> int:
        return len(self.rho)

    def transition(self, growth_m: float) -> tuple[np.ndarray, np.ndarray]:
        """(F, B) per component for an application of model growth ``growth_m`` [m]: (M, 3, 3), (M, 3, 1);
        the control input is u = [g] (B = [1, 0, 0]' for the data-driven components, 0 for the model)."""
        m = self.size
        F = np.zeros((m, DIM, DIM))
        F[:, 0, 0] = F[:, 2, 2] = 1.0
        F[:, 1, 1] = self.rho
        F[:, 0, 1] = np.where(self.model, growth_m, 1.0)
        F[self.accel, 0, 2] = 0.5
        F[self.accel, 1, 2] = 1.0
        B = np.zeros((m, DIM, 1))
        B[~self.model, 0, 0] = 1.0
        return F, B

    def projection(self, n: np.ndarray, mean_growth_m: float,
                   keep: np.ndarray | slice = slice(None)) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Clearance n applications ahead, Y_n = c + h1 x_1 + h2 x_2 + o, per kept component: (h1, h2, o),
        each of shape n.shape + (kept,).

        Steady: h1 = n; exponential: h1 = (rho^n - 1) / (rho - 1); constant acceleration: h1 = n,
        h2 = n^2 / 2; model: h1 = n gbar, o = 0; o = n gbar for the others (gbar: the model's mean
        growth per application so far [m]). rho^n is capped at e^100 (beyond any limit).
        """
        n = np.asarray(n, float)[..., None]
        rho, model = self.rho[keep], self.model[keep]
        log_rho = np.log(rho)
        grows = log_rho > 0.0
        with np.errstate(over="ignore", invalid="ignore"):
            geometric = np.expm1(np.minimum(n * log_rho, 100.0)) / np.where(grows, rho - 1.0, 1.0)
        h1 = np.where(model, n * mean_growth_m, np.where(grows, geometric, n))
        h2 = np.where(self.accel[keep], 0.5 * n * n, 0.0)
        return h1, h2, np.where(model, 0.0, n * mean_growth_m)

    def moments(self, bank: Bank, n: np.ndarray, mean_growth_m: float,
                keep: np.ndarray | slice = slice(None)) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Growth n applications ahead, G_n = Y_n - c, per kept component: its mean [m], its variance
        [m^2] and its covariance with the clearance c [m^2]."""
        h1, h2, o = self.projection(n, mean_growth_m, keep)
        x, P = bank.x[keep], bank.P[keep]
        mean = h1 * x[:, 1] + h2 * x[:, 2] + o
        var = h1 * h1 * P[:, 1, 1] + 2.0 * h1 * h2 * P[:, 1, 2] + h2 * h2 * P[:, 2, 2]
        cov_c = h1 * P[:, 0, 1] + h2 * P[:, 0, 2]
        return mean, var, cov_c


class Bank:
    """Means, covariances and log weights of the M components, and the observation-noise scale.

    Plain arrays, so the bank copies and serialises exactly (``to_dict`` / ``from_dict``).
    """

    def __init__(self, x: np.ndarray, P: np.ndarray, logw: np.ndarray, noise_sum: float, noise_count: float):
        self.x = np.array(x, float)  # (M, 3)
        self.P = np.array(P, float)  # (M, 3, 3)
        self.logw = np.array(logw, float)  # (M,)
        self.noise_sum, self.noise_count = float(noise_sum), float(noise_count)

    @classmethod
    def prior(cls, hyp: Hypotheses, config: MonitorConfig, clearance_m: float, clearance_var_m2: float,
              rate_std_m: float, *, factor: float = 1.0, factor_var: float | None = None,
              clearance_factor_cov: float = 0.0) -> Bank:
        """Every component at the clearance prior; r ~ N(0, rate_std^2), f ~ N(factor, factor_var),
        a ~ N(0, sigma_a0^2) with sigma_a0 = 2 rate_std / N_min (the fastest acceleration consumes
        the margin from rest in N_min applications)."""
        m = hyp.size
        x = np.zeros((m, DIM))
        x[:, 0] = clearance_m
        x[hyp.model, 1] = factor
        P = np.zeros((m, DIM, DIM))
        P[:, 0, 0] = clearance_var_m2
        P[:, 1, 1] = rate_std_m ** 2
        P[hyp.model, 1, 1] = config.initial_factor_std ** 2 if factor_var is None else factor_var
        P[hyp.model, 0, 1] = P[hyp.model, 1, 0] = clearance_factor_cov
        P[hyp.accel, 2, 2] = (2.0 * rate_std_m / config.min_cycles_for_life) ** 2
        nu0 = config.noise_scale_prior_cycles
        return cls(x, P, hyp.log_prior.copy(), nu0, nu0)

    def copy(self) -> Bank:
        return Bank(self.x, self.P, self.logw, self.noise_sum, self.noise_count)

    # ---------------------------------------------------------------- filter steps
    @property
    def noise_scale(self) -> float:
        """beta: measured observation variance over the error budget's [-]."""
        return self.noise_sum / self.noise_count

    def predict(self, hyp: Hypotheses, config: MonitorConfig, growth_m: float) -> np.ndarray:
        """x <- F x + B g, P <- F P F' (one filterpy predict of the stacked bank, module docstring),
        then P += Q for one application; returns F (M, 3, 3)."""
        kalman = load_filterpy()
        F, B = hyp.transition(growth_m)
        m = hyp.size
        x, P = kalman.predict(self.x.ravel(), block_diag(self.P), block_diag(F), 0.0, np.array([growth_m]),
                              B.reshape(m * DIM, 1))
        self.x, self.P = x.reshape(m, DIM), diagonal_blocks(P, m)
        self.P[:, 0, 0] += (config.growth_scatter * growth_m) ** 2
        rate_noise = np.where(hyp.model, config.factor_drift_per_cycle, hyp.wander * np.abs(self.x[:, 1]))
        self.P[:, 1, 1] += rate_noise ** 2
        return F

    def open(self, hyp: Hypotheses, clearance_var_m2: float, rate_var_m2: float, factor_var: float) -> None:
        """Let the clearance and/or the growth rate jump here: add their prior variances (tracker.py)."""
        self.P[:, 0, 0] += clearance_var_m2
        self.P[:, 1, 1] += np.where(hyp.model, factor_var, rate_var_m2)

    def innovation(self, observed_m: float, budget_var_m2: float) -> tuple[np.ndarray, np.ndarray]:
        """(y, S) per component: residual z - c [m] and its variance P_cc + beta R [m^2]."""
        return observed_m - self.x[:, 0], self.P[:, 0, 0] + self.noise_scale * budget_var_m2

    def update(self, config: MonitorConfig, observed_m: float, budget_var_m2: float, y: np.ndarray,
               S: np.ndarray) -> np.ndarray:
        """Fuse the observation ``observed_m`` [m] (innovations y, S from :meth:`innovation`): one
        filterpy Joseph-form update of the stacked bank, H = blkdiag([1, 0, 0]), R = beta R_k I_M
        (module docstring); returns the gains K = P H' / S (M, 3) of the prior P."""
        kalman = load_filterpy()
        m = self.x.shape[0]
        prior_cc = self.P[:, 0, 0].copy()
        K: np.ndarray = self.P[:, :, 0] / S[:, None]
        H = np.zeros((m, m * DIM))
        H[np.arange(m), np.arange(0, m * DIM, DIM)] = 1.0
        R = np.diag(np.full(m, self.noise_scale * budget_var_m2))
        x, P = kalman.update(self.x.ravel(), block_diag(self.P), np.full(m, observed_m), R, H)
        self.x, self.P = x.reshape(m, DIM), diagonal_blocks(P, m)
        self.P = 0.5 * (self.P + self.P.transpose(0, 2, 1))
        self.logw = self.logw - 0.5 * (_LOG_2PI + np.log(S) + y * y / S)
        w = self.weights()
        sharp = prior_cc < budget_var_m2  # clearance predicted better than one observation measures it
        if w[sharp].sum() > 0.5:
            sample = np.maximum(y * y - prior_cc, 0.0) / budget_var_m2
            self.noise_sum += float(w[sharp] @ sample[sharp] / w[sharp].sum())
            self.noise_count += 1.0
        eps = config.regime_change_per_cycle
        with np.errstate(divide="ignore"):
            self.logw = np.log((1.0 - eps) * w + eps / w.size)
        return K

    # ---------------------------------------------------------------- summaries
    def weights(self) -> np.ndarray:
        w: np.ndarray = np.exp(self.logw - np.max(self.logw))
        normalised: np.ndarray = w / w.sum()
        return normalised

    def clearance(self) -> tuple[float, float]:
        """Mixture mean and standard deviation of the clearance [m]."""
        w, c = self.weights(), self.x[:, 0]
        mean = float(w @ c)
        var = float(w @ (self.P[:, 0, 0] + (c - mean) ** 2))
        return mean, math.sqrt(max(var, 0.0))

    def growth_rate(self, hyp: Hypotheses, mean_growth_m: float) -> tuple[float, float]:
        """Mixture mean and standard deviation of the next application's clearance growth [m]."""
        mean_i, var_i, _ = hyp.moments(self, np.array(1.0), mean_growth_m)
        w = self.weights()
        mean = float(w @ mean_i)
        return mean, math.sqrt(max(float(w @ (var_i + (mean_i - mean) ** 2)), 0.0))

    # ---------------------------------------------------------------- persistence
    def to_dict(self) -> dict[str, Any]:
        return {"x": self.x.tolist(), "P": self.P.tolist(), "logw": self.logw.tolist(),
                "noise_sum": self.noise_sum, "noise_count": self.noise_count}

    @classmethod
    def from_dict(cls, data: dict[str, Any], size: int) -> Bank:
        """Inverse of :meth:`to_dict`; ValueError when shapes or values are wrong."""
        x, P, logw = (np.asarray(data[k], float) for k in ("x", "P", "logw"))
        if x.shape != (size, DIM) or P.shape != (size, DIM, DIM) or logw.shape != (size,):
            raise ValueError(f"filter bank of {size} components expected, got shapes {x.shape}, {P.shape}")
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(P)) and not np.any(np.isnan(logw))):
            raise ValueError("filter bank holds non-finite numbers")
        noise_sum, noise_count = float(data["noise_sum"]), float(data["noise_count"])
        if not (noise_count > 0.0 and noise_sum >= 0.0 and math.isfinite(noise_sum)):
            raise ValueError("filter bank noise scale is not a positive number")
        return cls(x, P, logw, noise_sum, noise_count)

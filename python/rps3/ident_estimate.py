"""The estimators on a stacked regressor (docs/identification.md,
"Estimators"): ordinary and weighted least squares and instrumental
variables, with the parameters' covariance and intervals; rps3.ident
re-exports every name."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from rps3.ident import COND_MAX, Base, _column_scale, _need, _r_factor, _stacked, check_excitation


@dataclass(frozen=True)
class Estimate:
    """A least-squares estimate with its covariance."""

    theta: np.ndarray        #: the estimated parameters, (p,)
    names: tuple[str, ...]   #: their names
    cov: np.ndarray          #: covariance of theta, (p, p)
    ci95: np.ndarray         #: 95 % intervals, (p, 2)
    sigma: np.ndarray        #: noise standard deviation per actuator [N], (3,)
    residual: np.ndarray     #: F - Y theta, (N,) [N]
    cond: float              #: condition number of the column-scaled regressor
    dof: int                 #: rows minus parameters
    method: str
    #: "iid" (cov from independent residuals) or "filtered" (the sandwich
    #: of the noise's known correlation over the samples: filtered data)
    cov_kind: str = "iid"

    @property
    def std(self) -> np.ndarray:
        return np.sqrt(np.diag(self.cov))


def _prepare(Y: ArrayLike, F: ArrayLike, base: Base | None,
             names: tuple[str, ...] | None, cond_max: float):
    Ya, Fa, act = _stacked(Y, F)
    if base is not None:
        Ya = base.reduce(Ya)
        nm = base.base_names
    else:
        nm = tuple(names) if names is not None else tuple(
            f"p{k}" for k in range(Ya.shape[1]))
    if len(nm) != Ya.shape[1]:
        raise ValueError(f"names: {len(nm)} names for {Ya.shape[1]} columns")
    if Ya.shape[0] <= Ya.shape[1]:
        raise ValueError(f"Y: {Ya.shape[0]} rows for {Ya.shape[1]} parameters")
    cond = check_excitation(Ya, nm, cond_max)
    return Ya, Fa, act, nm, cond


def _tquant(dof: int) -> float:
    return float(_need("scipy.stats").t.ppf(0.975, dof))


def _corr_cov(Yw: np.ndarray, Fw: np.ndarray, theta: np.ndarray, act: np.ndarray,
              corr: np.ndarray) -> np.ndarray:
    """Covariance of the least-squares theta of the (weighted) rows Yw, Fw
    stacked time-major, three a sample, when each actuator's noise is
    correlated over the samples as ``corr`` (n, n) (the noise of unit
    variance before filtering, after it) and independent across the
    actuators: B^-1 (sum_a c_a Y_a^T corr Y_a) B^-1, B = Yw^T Yw, Y_a the
    actuator's rows, c_a its unfiltered noise variance from the
    residuals, |r_a|^2 / (tr(corr) (1 - p / N))."""
    N, p = Yw.shape
    r = Fw - Yw @ theta
    d = _column_scale(Yw)
    Ys = Yw / d
    S = np.zeros((p, p))
    tr = float(np.trace(corr))
    for a in range(3):
        Ya = Ys[act == a]
        ra = r[act == a]
        S += (ra @ ra) / (tr * (1.0 - p / N)) * (Ya.T @ corr @ Ya)
    Bi = np.linalg.inv(Ys.T @ Ys)
    return (Bi @ S @ Bi) / np.outer(d, d)


def _finish(theta, cov, Ya, Fa, act, nm, cond, method, sigma=None, cov_kind="iid"):
    r = Fa - Ya @ theta
    dof = Ya.shape[0] - Ya.shape[1]
    if sigma is None:
        sigma = np.array([np.sqrt(np.mean(r[act == a] ** 2)) for a in range(3)])
    half = _tquant(dof) * np.sqrt(np.diag(cov))
    return Estimate(theta, nm, cov, np.column_stack([theta - half, theta + half]),
                    sigma, r, cond, dof, method, cov_kind)


def ols(Y: ArrayLike, F: ArrayLike, *, base: Base | None = None,
        names: tuple[str, ...] | None = None, cond_max: float = COND_MAX,
        noise_corr: np.ndarray | None = None) -> Estimate:
    """Ordinary least squares, theta = argmin |F - Y theta|^2, on the base
    regressor (``base`` given) or on Y as it is.  cov = s^2 (Y^T Y)^-1,
    s^2 = |r|^2 / (N - p); 95 % intervals theta +- t(0.975, N - p) std.
    With ``noise_corr`` (n, n) (rows time-major, three a sample, each
    actuator's noise correlated over the samples as given, as after
    filtering and decimation) cov is the sandwich of that correlation
    instead (``cov_kind`` "filtered").

    Raises:
        NotExcitingError: the data do not determine the parameters.
    """
    Ya, Fa, act, nm, cond = _prepare(Y, F, base, names, cond_max)
    theta, cov = _lsq(Ya, Fa)
    kind = "iid"
    if noise_corr is not None:
        cov, kind = _corr_cov(Ya, Fa, theta, act, noise_corr), "filtered"
    return _finish(theta, cov, Ya, Fa, act, nm, cond, "ols", cov_kind=kind)


def _lsq(Ya: np.ndarray, Fa: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Least squares by a QR of the column-scaled Y: theta and
    s^2 (Y^T Y)^-1, s^2 = |r|^2 / (N - p)."""
    d = _column_scale(Ya)
    p = Ya.shape[1]
    Ra = _r_factor(np.column_stack([Ya / d, Fa]))   # [[R, Q^T F], [0, |r|]]
    Ri = np.linalg.inv(Ra[:p, :p])
    theta = (Ri @ Ra[:p, p]) / d
    r = Fa - Ya @ theta
    s2 = r @ r / (Ya.shape[0] - Ya.shape[1])
    cov = s2 * (Ri @ Ri.T) / np.outer(d, d)
    return theta, cov


def wls(Y: ArrayLike, F: ArrayLike, *, base: Base | None = None,
        names: tuple[str, ...] | None = None, cond_max: float = COND_MAX,
        noise_corr: np.ndarray | None = None) -> Estimate:
    """Weighted least squares with each actuator's noise variance
    estimated from an OLS fit's residuals, sigma_a^2 = |r_a|^2 / (N_a -
    p N_a / N) (the rows' share of the degrees of freedom); rows weighted
    by 1 / sigma_a.  cov = (Y^T W Y)^-1 s_w^2, s_w^2 the weighted residual
    variance (about 1); with ``noise_corr`` the sandwich of that
    correlation over the weighted rows instead (see :func:`ols`)."""
    Ya, Fa, act, nm, cond = _prepare(Y, F, base, names, cond_max)
    theta0, _ = _lsq(Ya, Fa)
    r0 = Fa - Ya @ theta0
    N, p = Ya.shape
    sig = np.zeros(3)
    for a in range(3):
        Na = int(np.sum(act == a))
        sig[a] = np.sqrt(r0[act == a] @ r0[act == a] / (Na - p * Na / N))
    if np.any(sig <= 0):
        raise ValueError("wls: an actuator's residual variance is zero "
                         "(noise-free data: use ols)")
    w = 1.0 / sig[act]
    Yw, Fw = Ya * w[:, None], Fa * w
    theta, cov = _lsq(Yw, Fw)
    kind = "iid"
    if noise_corr is not None:
        cov, kind = _corr_cov(Yw, Fw, theta, act, noise_corr), "filtered"
    return _finish(theta, cov, Ya, Fa, act, nm, cond, "wls", sigma=sig, cov_kind=kind)


def iv(Y: ArrayLike, F: ArrayLike, Z: ArrayLike, *, base: Base | None = None,
       names: tuple[str, ...] | None = None, cond_max: float = COND_MAX) -> Estimate:
    """Instrumental variables: theta = (Z^T Y)^-1 Z^T F, with instruments Z
    of Y's shape correlated with the noise-free regressor and not with the
    noise in Y (e.g. the regressor of the reference trajectory, or of a
    simulation with a previous estimate).  cov = s^2 (Z^T Y)^-1 Z^T Z
    (Y^T Z)^-1, s^2 = |F - Y theta|^2 / (N - p)."""
    Ya, Fa, act, nm, cond = _prepare(Y, F, base, names, cond_max)
    Za, _, _ = _stacked(Z)
    if base is not None:
        Za = base.reduce(Za)
    if Za.shape != Ya.shape:
        raise ValueError(f"Z: shape {Za.shape} differs from Y's {Ya.shape}")
    check_excitation(Za, nm, cond_max)
    ZY = Za.T @ Ya
    theta = np.linalg.solve(ZY, Za.T @ Fa)
    r = Fa - Ya @ theta
    s2 = r @ r / (Ya.shape[0] - Ya.shape[1])
    ZYi = np.linalg.inv(ZY)
    cov = s2 * ZYi @ (Za.T @ Za) @ ZYi.T
    return _finish(theta, cov, Ya, Fa, act, nm, cond, "iv")



"""Figures of an identification in rps3.plot's style, one function each:
estimates with their 95 % intervals against the truth, residuals, the
exciting trajectory, and a prediction on held-out data.  Each writes
``path`` (.pdf, .svg or .png) and returns it.
"""

from __future__ import annotations

import os

import numpy as np
from numpy.typing import ArrayLike

from rps3 import ident_estimate as _ie
from rps3 import ident_paper as _ip
from rps3 import plot

_POSE = (("alpha", "rad"), ("beta", "rad"), ("z_c", "m"))


def estimates(path: str | os.PathLike[str], est: _ie.Estimate,
              truth: ArrayLike | None = None) -> str:
    """Each base parameter's estimate with its 95 % interval, relative to
    the truth (or to the estimate itself without one): 1 is exact."""
    ref = np.asarray(est.theta if truth is None else truth, float)
    sc = np.where(np.abs(ref) > 0, np.abs(ref), 1.0)
    y = np.arange(len(est.names))
    fig, ax = plot.subplots(figsize=(6, 0.35 * len(y) + 1.2))
    lo = (est.theta - est.ci95[:, 0]) / sc
    hi = (est.ci95[:, 1] - est.theta) / sc
    ax.errorbar(est.theta / sc * np.sign(ref), y, xerr=[lo, hi], fmt="o", color="k",
                markerfacecolor="none", capsize=3, label="estimate, 95 % interval")
    if truth is not None:
        ax.axvline(1.0, color="0.5", linestyle="--", label="truth")
    ax.set_yticks(y, list(est.names))
    ax.invert_yaxis()
    ax.set_xlabel("estimate / truth [-]" if truth is not None else "estimate / itself [-]")
    plot.legend(ax)
    return plot.save(fig, path)


def residuals(path: str | os.PathLike[str], t: ArrayLike, est: _ie.Estimate) -> str:
    """The residuals F - Y theta [N] per actuator over time, with each
    actuator's noise level +-2 sigma."""
    tt = np.asarray(t, float)
    r = np.asarray(est.residual, float).reshape(len(tt), 3)
    fig, ax = plot.subplots()
    plot.links(ax, tt, r, "residual")
    for i in range(3):
        ax.axhline(2 * est.sigma[i], color="0.6", linestyle=plot.LINK_STYLES[i], linewidth=0.8)
        ax.axhline(-2 * est.sigma[i], color="0.6", linestyle=plot.LINK_STYLES[i], linewidth=0.8)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("F - Y theta [N]")
    plot.legend(ax)
    plot.note(fig, "grey: +-2 sigma, each actuator's estimated noise level")
    return plot.save(fig, path)


def excitation(path: str | os.PathLike[str], fourier: _ip.Fourier,
               samples: int = 500) -> str:
    """The exciting trajectory over one period: alpha, beta, z_c."""
    t = np.linspace(0.0, fourier.period, samples)
    q, _, _ = fourier.eval(t)
    fig, axs = plot.subplots(3, 1, sharex=True, figsize=(6, 5))
    for k, (name, unit) in enumerate(_POSE):
        axs[k].plot(t, q[:, k], color="k", label=name)
        axs[k].set_ylabel(f"{name} [{unit}]")
    axs[-1].set_xlabel("t [s]")
    axs[0].set_title(f"Fourier series, {fourier.harmonics} harmonics of "
                     f"{fourier.f0:g} Hz")
    return plot.save(fig, path)


def prediction(path: str | os.PathLike[str], t: ArrayLike, F: ArrayLike,
               F_pred: ArrayLike) -> str:
    """Held-out forces [N] measured and predicted by the identified
    parameters, per actuator, with the RMS error in the note."""
    tt = np.asarray(t, float)
    Fm = np.asarray(F, float)
    Fp = np.asarray(F_pred, float)
    fig, ax = plot.subplots()
    plot.links(ax, tt, Fm, "measured", color="0.6")
    plot.links(ax, tt, Fp, "predicted", color="k")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("F [N]")
    plot.legend(ax, ncol=2)
    rms = np.sqrt(np.mean((Fm - Fp) ** 2)) / np.sqrt(np.mean(Fm**2))
    plot.note(fig, f"held-out data: RMS prediction error {rms:.2%} of the RMS force")
    return plot.save(fig, path)

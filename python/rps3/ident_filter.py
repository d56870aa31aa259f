"""Zero-phase filtering and differentiation of measured signals for
identification (docs/identification.md, "Estimators"); answered through
:mod:`rps3.ident` too.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from rps3.ident import _need

#: order of the Butterworth filter of :func:`zero_phase_filter` (applied
#: forward and backward: the result has order 8 and zero phase)
FILTER_ORDER = 4


def zero_phase_filter(x: ArrayLike, fs: float, cutoff: float,
                      order: int = FILTER_ORDER) -> np.ndarray:
    """x (n, ...) low-pass filtered along axis 0 by a Butterworth filter of
    the given order and cut-off [Hz] applied forward and backward
    (scipy.signal.filtfilt): zero phase, gain |H(f)|^2, so 1/2 (-6 dB) at
    the cut-off.  Choose the cut-off a few times (3-5) above the highest
    frequency of the excitation and well below the noise's band.  Apply
    the same filter to the regressor's columns, the forces and any
    instruments (parallel filtering: their distortions, Coulomb's sign
    steps among them, then match), drop the ends' transients and decimate
    to about 2.5 times the cut-off so the remaining noise is about white
    (docs/identification.md, "Estimators")."""
    signal = _need("scipy.signal")
    if not 0 < cutoff < fs / 2:
        raise ValueError(f"cutoff: {cutoff} Hz is not inside (0, fs/2 = {fs / 2} Hz)")
    b, a = signal.butter(order, cutoff / (fs / 2))
    return np.asarray(signal.filtfilt(b, a, np.asarray(x, float), axis=0))


def differentiate(t: ArrayLike, x: ArrayLike, cutoff: float,
                  order: int = FILTER_ORDER) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions sampled at uniform times t (n,) [s] filtered
    (:func:`zero_phase_filter`, cut-off [Hz]) and differentiated twice by
    second-order central differences (np.gradient): (x, x', x'')."""
    ta = np.asarray(t, float)
    h = np.diff(ta)
    if ta.ndim != 1 or len(ta) < 3 or np.ptp(h) > 1e-9 * h.mean():
        raise ValueError("t: expected at least 3 uniformly spaced sample times")
    xf = zero_phase_filter(x, 1.0 / h.mean(), cutoff, order)
    dx = np.gradient(xf, ta, axis=0)
    return xf, dx, np.gradient(dx, ta, axis=0)

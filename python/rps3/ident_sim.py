"""Identification on simulated data (docs/identification.md, "Monte Carlo
on simulated data"): the paper model simulated (rps3.sim) while a PD law
tracks an exciting trajectory, force noise added, the fit repeated.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rps3 import ident as _id
from rps3 import ident_io as _io
from rps3 import ident_paper as _ip

#: a base parameter whose true value carries at most this share of the
#: RMS force is taken as zero (rounding of a zero sum): no relative error
ZERO_SHARE = 1e-12
#: a base parameter counts in the error statistics when its columns carry
#: at least this share of the RMS force (smaller ones are within the noise)
CONTRIBUTION_MIN = 0.01


@dataclass(frozen=True)
class Simulated:
    """A simulated run: times t (n,) [s], lengths l, rates dl [m/s],
    accelerations ddl [m/s^2] (the plant's forward dynamics at the applied
    forces), applied forces F [N], all (n, 3); the true parameters of the
    set."""

    t: np.ndarray
    l: np.ndarray
    dl: np.ndarray
    ddl: np.ndarray
    F: np.ndarray
    theta_true: np.ndarray
    pset: _ip.PaperSet
    geometry: _ip.Geometry


def simulate(fourier: _ip.Fourier, truth: dict[str, Any], *, periods: float = 1.0,
             dt: float = 0.005, geometry: _ip.Geometry | None = None,
             pset: _ip.PaperSet | None = None, kp: float = 2000.0,
             kd: float = 40.0) -> Simulated:
    """The plant of Model arguments ``truth`` (every effect its arguments
    give) under the library's PD law (kp [N/m], kd [N s/m], 1 kHz) tracking
    the Fourier trajectory, sampled every dt [s] over ``periods``
    periods."""
    from rps3 import control, dynamics, sim, trajectory

    geo = geometry or _ip.Geometry()
    ps = pset or _ip.PaperSet()
    effects = ["platform_gravity", "link_gravity", "platform_inertia", "link_inertia"]
    if "payload" in truth:
        effects.append("payload")
    if "friction" in truth:
        effects.append("pin_friction")
    fr = dict(truth.get("friction", {}))
    if fr:
        fr.setdefault("vreg", geo.vreg)
    args = {k: v for k, v in truth.items() if k not in ("friction", "d")}
    if "d" in truth and truth["d"] != geo.d:
        raise ValueError(f"truth: d = {truth['d']} differs from the geometry's {geo.d}")
    plant = geo.model(effects=effects, **args, **({"friction": fr} if fr else {}))
    span = periods * fourier.period
    rows = np.linspace(0.0, span, int(round(span / 0.01)) + 1)
    q, dq, ddq = fourier.eval(rows)
    n = int(round(span / dt)) + 1
    traj = trajectory.table(rows, q, dq, ddq, samples=n, model=plant)
    res = sim.simulate(plant, control.pd(plant, traj, kp=kp, kd=kd), traj.t,
                       traj.pose[0], traj.dpose[0])
    keep = np.all(np.isfinite(res.force), axis=1)
    t, l, dl, F = res.t[keep], res.l[keep], res.dl[keep], res.force[keep]
    ddl = dynamics.forward(plant, l, dl, F).ddl
    theta = _ip.paper_parameters(pset=ps, R=geo.R, rho=geo.rho, **truth)
    return Simulated(t, l, dl, np.asarray(ddl), F, theta, ps, geo)


@dataclass(frozen=True)
class SimulatedGeneral:
    """A general model's motion: times t (n,) [s], lengths l, rates dl
    [m/s], accelerations ddl [m/s^2], the forces F [N] of the library's
    inverse dynamics, all (n, 3); the layout fitted, the truth's layout
    parameters (``theta_true``, layout.matrix @ theta_true = its 82
    standard parameters) and the geometry."""

    t: np.ndarray
    l: np.ndarray
    dl: np.ndarray
    ddl: np.ndarray
    F: np.ndarray
    theta_true: np.ndarray
    layout: _id.Layout
    geometry: _ip.Geometry


#: Y theta_true against the truth model's forces in simulate_general:
#: one formulation summed two ways (rounding, measured ~1e-15 of the
#: forces); above it the truth is not of the layout or the geometry
TRUTH_TOL = 1e-9


def simulate_general(model: Any, fourier: _ip.Fourier, layout: _id.Layout, *,
                     periods: float = 1.0, dt: float = 0.001,
                     geometry: _ip.Geometry | None = None) -> SimulatedGeneral:
    """The forces of ``model`` (an rps3.Model, general bodies and friction,
    its effects those of the layout: the paper's four and the layout's
    friction kinds) by the library's inverse dynamics along the Fourier
    series, sampled every dt [s] over ``periods`` periods, with the exact
    lengths, rates and accelerations (rps3.velocity.pose_rates).  The
    geometry (default the model's R, rho, g, vreg 0) is the fit's: its
    vreg must be the model's friction laws'.

    Raises:
        ValueError: the model's parameters are not of the layout (e.g.
            legs that differ for an identical layout), or its forces are
            not the layout's regressor times them (other effects, another
            geometry or vreg).
    """
    from rps3 import ident_c as _c
    from rps3 import ident_excite as _ix
    from rps3 import velocity

    geo = geometry or _ip.Geometry(R=model.R, rho=model.rho, g=model.g)
    std = _c.std_params(model)
    theta = np.linalg.lstsq(layout.matrix, std, rcond=None)[0]
    off = np.abs(layout.matrix @ theta - std)
    if off.max() > TRUTH_TOL * max(np.abs(std).max(), 1e-300):
        j = int(np.argmax(off))
        raise ValueError(f"model: its {_id.STANDARD_NAMES[j]} is not of the layout "
                         f"(legs={layout.legs}, friction={layout.friction}, "
                         f"per leg {layout.per_leg})")
    t = np.arange(int(round(periods * fourier.period / dt)) + 1) * dt
    q, dq, ddq = fourier.eval(t)
    F = np.asarray(model.inverse(q, dq, ddq).force)
    Y = _ix.layout_regressor(q, dq, ddq, geo, layout)
    if np.abs(Y @ theta - F).max() > TRUTH_TOL * np.abs(F).max():
        raise ValueError("model: its forces are not the layout's regressor times its "
                         "parameters: effects other than the paper's four and the "
                         "layout's friction, or a geometry (R, rho, g, vreg) other "
                         "than the fit's")
    mot = velocity.pose_rates(model, q, dq, ddq)
    return SimulatedGeneral(t, np.asarray(mot.l), np.asarray(mot.dl), np.asarray(mot.ddl),
                            F, theta, layout, geo)


@dataclass(frozen=True)
class Study:
    """The statistics of a Monte Carlo study; with ``consistent`` or a
    held-out motion, per draw (arrays of ``runs``, empty when not asked):
    the consistent fit's flags and the held-out forces' NRMSE of each
    fit."""

    runs: int
    names: tuple[str, ...]           #: base parameters
    truth: np.ndarray                #: their true values
    contribution: np.ndarray         #: RMS force share of each (truth)
    counted: np.ndarray              #: contribution >= CONTRIBUTION_MIN
    median_rel_error: np.ndarray     #: per parameter, |theta - truth| / |truth| (NaN: truth 0)
    bias: np.ndarray                 #: mean (theta - truth) / |truth|
    coverage: np.ndarray             #: share of runs whose 95 % interval holds the truth
    source: dict[str, str]
    #: the consistent fit physically consistent (False: it failed)
    consistent: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    #: the consistent fit met its optimality test
    converged: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    #: held-out NRMSE of the estimate (Y_base theta) ...
    nrmse_wls: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: ... and of the consistent fit (Y pi; NaN: no consistent fit)
    nrmse_consistent: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: the paper set's consistent fit maps onto Model's arguments (empty
    #: for a layout): see _consistent_of
    maps: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))

    @property
    def ratio(self) -> np.ndarray:
        """Per draw, the held-out NRMSE of the consistent fit over the
        estimate's."""
        return self.nrmse_consistent / self.nrmse_wls

    def summary(self) -> str:
        lines = [f"{self.runs} runs; rates and accelerations: "
                 f"{self.source.get('rates', '?')}"]
        for k, n in enumerate(self.names):
            lines.append(f"{n:12s} share {self.contribution[k]:7.2%}  median |err| "
                         f"{self.median_rel_error[k]:9.3%}  bias {self.bias[k]:+9.3%}  "
                         f"coverage {self.coverage[k]:6.1%}"
                         + ("" if self.counted[k] else
                            "  (truth 0: not counted)" if np.isnan(self.bias[k]) else
                            "  (below 1 %: not counted)"))
        c = self.counted
        lines.append(f"counted: median relative error {np.median(self.median_rel_error[c]):.3%}, "
                     f"coverage {np.mean(self.coverage[c]):.1%}")
        runs = self.runs
        if len(self.consistent):
            lines.append(f"consistent fit: physically consistent in {self.consistent.sum()}/{runs} "
                         f"draws ({np.mean(self.consistent):.1%}), converged "
                         f"{self.converged.sum()}/{runs} ({np.mean(self.converged):.1%})")
        if len(self.maps):
            lines.append(f"consistent fit maps onto Model's arguments (link_Ic >= 0 at the "
                         f"geometry's d, not constrained) in {self.maps.sum()}/{runs} draws")
        if len(self.nrmse_wls):
            line = f"held-out NRMSE: WLS median {np.median(self.nrmse_wls):.4%}"
            r = self.ratio[np.isfinite(self.ratio)]
            if len(self.nrmse_consistent):
                line += (f", consistent median {np.nanmedian(self.nrmse_consistent):.4%}"
                         if len(r) else ", consistent: no fit")
            lines.append(line)
            if len(r):
                lines.append(f"held-out NRMSE consistent / WLS: median {np.median(r):.4f}, "
                             f"max {r.max():.4f} (over {len(r)} fits)")
        return "\n".join(lines)


def _nrmse(pred: np.ndarray, meas: np.ndarray) -> float:
    """RMS(pred - meas) / RMS(meas), over every sample and actuator."""
    return float(np.sqrt(np.mean((pred - meas) ** 2) / np.mean(meas**2)))


def _holdout_regressor(s: Simulated | SimulatedGeneral,
                       h: Simulated | SimulatedGeneral) -> np.ndarray:
    """The fitted parameters' regressor (n, 3, p: the layout's, or the
    paper set's) along the held-out motion ``h`` at its exact states,
    which must be of the same kind, set or layout and geometry as s."""
    if type(h) is not type(s) or h.geometry != s.geometry:
        raise ValueError("holdout: another kind of simulation or another geometry "
                         "than the fitted one's")
    d = _io.Data("held-out", h.t, h.l, h.dl, h.ddl, None, "",
                 {"rates": "measured", "accelerations": "measured"})
    _, q, dq, ddq, _ = _io.states(d, s.geometry)
    if isinstance(s, SimulatedGeneral):
        from rps3 import ident_excite as _ix

        assert isinstance(h, SimulatedGeneral)
        if h.layout != s.layout:
            raise ValueError("holdout: another layout than the fitted one's")
        return _ix.layout_regressor(q, dq, ddq, s.geometry, s.layout)
    assert isinstance(h, Simulated)
    if h.pset != s.pset:
        raise ValueError("holdout: another paper set than the fitted one's")
    return _ip.paper_regressor(q, dq, ddq, s.geometry, s.pset)


def monte_carlo(s: Simulated | SimulatedGeneral, *, runs: int, force_noise: float = 0.01,
                stroke_noise: float | None = None, seed: int = 0,
                cutoff: float = _io.CUTOFF, method: str = "wls", consistent: bool = False,
                holdout: Simulated | SimulatedGeneral | None = None) -> Study:
    """``runs`` fits of the simulated data with Gaussian force noise of
    ``force_noise`` times each actuator's RMS force (different levels per
    actuator: ``wls`` by default, whose intervals assume them; OLS's
    assume one level and cover less); with
    ``stroke_noise`` [m], lengths with that noise and no rates or
    accelerations (the fit differentiates them with the cut-off [Hz]),
    else the simulation's exact states.  For a general model
    (:func:`simulate_general`) the layout's base parameters are fitted.

    With ``consistent``, each draw's physically consistent fit too: a
    general layout's of all its parameters (``fit(consistent=True)``),
    the paper set's by :func:`rps3.ident_io.paper_consistent`.  With
    ``holdout`` (another motion of the same truth, set or layout and
    geometry: a second :func:`simulate` or :func:`simulate_general`), its
    forces with noise of ``force_noise`` times each of its actuators' RMS
    force, drawn anew per draw, against each fit's prediction at its
    exact states: the estimate's Y_base theta and the consistent fit's
    Y pi, as RMS(predicted - measured) / RMS(measured) (NRMSE).

    Raises:
        ValueError: a held-out motion of another kind, set, layout or
            geometry; ``consistent`` for a paper set the data do not
            determine (rps3.ident_io.paper_consistent).
    """
    rng = np.random.default_rng(seed)
    # the held-out noise from a stream of its own: the fitted draws are
    # those of the same seed without a held-out motion
    rng_h = np.random.default_rng((seed, 1))
    rmsF = np.sqrt(np.mean(s.F**2, axis=0))
    ests, cis = [], []
    model: dict[str, Any]
    if isinstance(s, SimulatedGeneral):
        from rps3 import ident_excite as _ix

        base = _ix.layout_base(s.geometry, s.layout)
        model = dict(layout=s.layout, consistent=consistent)
    else:
        base = _ip.structural_base(s.geometry, s.pset)
        model = dict(pset=s.pset)
    truth = base.of(s.theta_true)
    Yh = None if holdout is None else _holdout_regressor(s, holdout)
    rmsH = None if holdout is None else np.sqrt(np.mean(holdout.F**2, axis=0))
    ok, conv, maps, e_wls, e_con = [], [], [], [], []
    src: dict[str, str] = {}
    contribution = np.zeros(len(truth))
    for k in range(runs):
        F = s.F + rng.normal(size=s.F.shape) * force_noise * rmsF
        if stroke_noise is None:
            d = _io.Data("simulated", s.t, s.l, s.dl, s.ddl, F, "",
                         {"rates": "measured", "accelerations": "measured"})
        else:
            ln = s.l + rng.normal(size=s.l.shape) * stroke_noise
            d = _io.Data("simulated", s.t, ln, None, None, F, "",
                         {"rates": "none", "accelerations": "none"})
        res = _io.fit(d, geometry=s.geometry, method=method, cutoff=cutoff, **model)
        ests.append(res.estimate.theta)
        cis.append(res.estimate.ci95)
        src = res.source
        if k == 0:
            Yb = res.Y.reshape(-1, len(truth))
            rms = np.sqrt(np.mean(res.F**2))
            contribution = np.sqrt(np.mean((Yb * truth) ** 2, axis=0)) / rms
        pi = None
        if consistent:
            good, cf, mp = _consistent_of(res)
            ok.append(good)
            if mp is not None:
                maps.append(mp)
            conv.append(cf is not None and cf.converged)
            pi = None if cf is None else cf.pi
        if holdout is not None:
            assert Yh is not None and rmsH is not None
            Fh = holdout.F + rng_h.normal(size=holdout.F.shape) * force_noise * rmsH
            e_wls.append(_nrmse(base.reduce(Yh) @ res.estimate.theta, Fh))
            if consistent:
                e_con.append(np.nan if pi is None else _nrmse(Yh @ pi, Fh))
    E = np.array(ests)
    C = np.array(cis)
    # a base parameter whose truth carries no force (zero, as a symmetric
    # body's products of inertia, up to rounding) has no relative error
    scale = np.where(contribution > ZERO_SHARE, np.abs(truth), np.nan)
    rel = (E - truth) / scale
    cover = np.mean((C[:, :, 0] <= truth) & (truth <= C[:, :, 1]), axis=0)
    return Study(runs, base.base_names, truth, contribution,
                 contribution >= CONTRIBUTION_MIN, np.median(np.abs(rel), axis=0),
                 rel.mean(axis=0), cover, src, np.array(ok, bool), np.array(conv, bool),
                 np.array(e_wls, float), np.array(e_con, float), np.array(maps, bool))


def _consistent_of(res: _io.Fit) -> tuple[bool, Any, bool | None]:
    """(physically consistent, the CFit or None, maps) of a draw's fit.
    A general layout's from ``fit``: its flag, the C fit's check and the
    consistency report of its parameters.  The paper set's by
    :func:`rps3.ident_io.paper_consistent`: the C fit's check and, again
    here, its bodies' pseudo-inertia eigenvalues and its >= 0 columns, as
    the fit constrains them (rps3.ident.paper_layout: the link's mass and
    centre free); ``maps``: whether its parameters map onto Model's
    arguments too (a link of mass md / d and link_Ic >= 0 at the
    geometry's d, which the fit does not constrain), None for a layout."""
    from rps3 import ident_c as _c
    from rps3 import ident_consistent as _ic

    if res.layout is not None:
        return bool(res.consistent), res.consistent_fit, None
    try:
        cf = _io.paper_consistent(res)
    except _id.InconsistentFitError:
        return False, None, False
    assert res.pset is not None
    ok = bool(cf.consistent)
    for body in cf.body:
        eig = np.linalg.eigvalsh(_id.pseudo_inertia(body))
        ok &= bool(eig.min() >= -_ic.EIG_TOL * max(np.abs(eig).max(), 1e-300))
    nonneg = cf.pi[_c.paper_layout([_c.C_PAPER_NAMES.index(n)
                                    for n in res.pset.names]).kind == 1]
    ok &= bool(np.all(nonneg >= -_ic.EIG_TOL * max(np.abs(nonneg).max(initial=0.0), 1e-300)))
    geo = res.geometry
    std = _ip.standard_of(cf.pi, res.pset, d=geo.d, R=geo.R, rho=geo.rho)
    return ok, cf, bool(std is not None and _ic.consistency_report(std[0], std[1]).ok)


#: the plant of the studies: Table II with a link inertia and pin friction
TRUTH: dict[str, Any] = {"M": 0.18, "m": 0.09, "d": 0.1524, "link_Ic": 2.0e-4,
                         "friction": {"viscous": 0.02, "coulomb": 0.01}}


#: the held-out motions of the studies: a random series (seed SEED_HOLDOUT)
#: about the excitations' centre, another base frequency and harmonics
SEED_HOLDOUT = 9


def study(runs: int = 200, seed: int = 1, out: str | None = None) -> str:
    """The full study (``make ident``): an optimised excitation, the
    simulated run over two periods, ``runs`` fits with measured states and
    ``runs`` with differentiated ones, each with the paper set's
    consistent fit and both fits' NRMSE on a held-out motion (a random
    series of 0.25 Hz, 4 harmonics, peak excursion (0.7, 0.08, 0.015),
    simulated alike over 8 s); the summaries (and figures into the
    directory ``out``)."""
    from rps3 import ident_excite as _ix

    geo = _ip.Geometry(vreg=0.01)
    ex = _ip.design(geometry=geo, seed=seed, f0=0.2, harmonics=5,
                    amplitude=(0.8, 0.1, 0.02), maxiter=2000)
    s = simulate(ex.fourier, TRUTH, periods=2.0, geometry=geo)
    fo = _ix.random_fourier(ex.fourier.q0, (0.7, 0.08, 0.015), 0.25, 4, seed=SEED_HOLDOUT)
    h = simulate(fo, TRUTH, periods=2.0, geometry=geo)
    a = monte_carlo(s, runs=runs, seed=seed, consistent=True, holdout=h)
    b = monte_carlo(s, runs=runs, seed=seed + 1, stroke_noise=1e-5, consistent=True,
                    holdout=h)
    text = (f"excitation: cond {ex.cond:.3g} (start {ex.cond_start:.3g}), converged "
            f"{ex.converged} ({ex.message}), seed {ex.seed}\n"
            f"--- force noise 1 % of RMS, measured states\n{a.summary()}\n"
            f"--- force noise 1 %, stroke noise 1e-5 m, differentiated states\n"
            f"{b.summary()}\n")
    if out:
        import os

        from rps3 import ident_plot

        os.makedirs(out, exist_ok=True)
        ident_plot.excitation(os.path.join(out, "ident_excitation.png"), ex.fourier)
        with open(os.path.join(out, "ident_study.txt"), "w", encoding="utf-8") as fh:
            fh.write(text)
    return text


def general_truth(legs: str = "identical", vreg: float = 0.01) -> Any:
    """The general model of configs/general_bodies.yaml (a plate with a
    bracket, tubes and rods, friction in pins and prismatic joints; both
    laws' vreg ``vreg``), as an rps3.Model with the paper's four effects
    and both friction kinds: with ``legs`` "each", leg 3's stiffer seal
    (Coulomb 0.6 N); "identical", the three legs alike."""
    from rps3.body import Body
    from rps3.model import DEFAULT_EFFECTS, Model

    platform = Body(0.25, [0.004, 0.0, -0.006], [0.00085, 0.00002, 0.0, 0.00088, 0.0, 0.0017])
    cylinder = Body(0.12, [0.08, 0.0, 0.0], [0.0000135, 0.0, 0.0, 0.000256, 0.0, 0.000256])
    piston = Body(0.08, [-0.06, 0.0, 0.0], [0.0000014, 0.0, 0.0, 0.000096, 0.0, 0.000096])
    pin = dict(viscous=0.002, coulomb=0.001, vreg=vreg)
    prism = [dict(viscous=3.0, coulomb=0.4 if i < 2 or legs != "each" else 0.6, vreg=vreg)
             for i in range(3)]
    return Model(bodies=dict(platform=platform, cylinder=cylinder, piston=piston),
                 friction=pin, prismatic_friction=prism if legs == "each" else prism[0],
                 effects=[*DEFAULT_EFFECTS, "pin_friction", "prismatic_friction"])


def study_general(runs: int = 200, seed: int = 1, legs: str = "identical",
                  dt: float = 0.001, periods: float = 2.0) -> str:
    """The Monte Carlo of a general layout (legs ``legs``, both friction
    kinds, the layout's default per-leg choice) on :func:`general_truth`:
    a random Fourier series (0.2 Hz, 6 harmonics, peak excursion (1.5,
    0.12, 0.03) about (0, 0.25, 0.31)), ``periods`` periods sampled every
    dt [s], ``runs`` WLS fits of 1 % force noise with measured states,
    each with the consistent fit of all the layout's parameters and both
    fits' NRMSE on a held-out motion (a random series of 0.25 Hz, 5
    harmonics, peak excursion (1.2, 0.1, 0.025), 8 s at the same dt);
    the summary."""
    from rps3 import ident_excite as _ix

    geo = _ip.Geometry(vreg=0.01)
    lay = _id.Layout(legs=legs)
    truth = general_truth(legs, geo.vreg)
    fo = _ix.random_fourier((0.0, 0.25, 0.31), (1.5, 0.12, 0.03), 0.2, 6, seed=3)
    s = simulate_general(truth, fo, lay, periods=periods, dt=dt, geometry=geo)
    fh = _ix.random_fourier((0.0, 0.25, 0.31), (1.2, 0.1, 0.025), 0.25, 5,
                            seed=SEED_HOLDOUT)
    h = simulate_general(truth, fh, lay, periods=2.0, dt=dt, geometry=geo)
    st = monte_carlo(s, runs=runs, seed=seed, consistent=True, holdout=h)
    return (f"layout legs={legs}, friction prismatic,pin: {len(st.names)} base "
            f"parameters, {len(s.t)} samples every {dt:g} s\n{st.summary()}\n")

"""Design optimisation of the manipulator: a design (geometry, joint
limits, masses), how good it is over a grid of poses and along a task,
and the optimisers that search the designs (docs/design-optimisation.md;
the indices are defined in docs/design.md).

    import rps3
    from rps3 import design
    ds = design.Design()                       # Table II, stroke [R, 2 R]
    g = design.grid(ds, n=(12, 8, 10))          # (alpha, beta, z_c)
    ev = design.evaluate(ds, g)                 # xarray Dataset
    float(ev["volume"]), float(ev["gti"])
    req = design.task(ds.replace(payload=0.5), rps3.trajectory.helix())
    req.peak_force                              # [N]

Every index is the library's (include/rps3.h, rps3_design_eval and
rps3_design_task_eval): this module checks arguments, lays out arrays and
names results.  SI units: lengths [m], angles [rad], masses [kg], the
workspace volume in pose coordinates [m rad^2].

The optimisers (``pareto``: NSGA-II of pymoo; ``optimise``: NLopt) are
optional dependencies: ``pip install 'rps3[design]'``.
"""

from __future__ import annotations

import dataclasses
import math
import threading
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from rps3 import _optimise
from rps3 import errors as _errors
from rps3._core import FloatArray, buf, text
from rps3._rps3 import ffi, lib
from rps3.errors import ReachError, error, points3, real_number
from rps3.model import Model

if TYPE_CHECKING:  # xarray is imported by evaluate alone
    import xarray as xr

    from rps3.trajectory import Spec, Trajectory

# ------------------------------------------------------------------ design

#: the fields of rps3_design, in the library's order, with their units
#: (the library's RPS3_DESIGN_FIELDS table; a test holds the two equal)
UNITS: dict[str, str] = {
    "R": "m", "rho": "1", "l_min": "m", "l_max": "m", "theta_min": "rad",
    "theta_max": "rad", "ball_max": "rad", "link_radius": "m", "M": "kg",
    "payload": "kg", "payload_height": "m", "actuator_mass": "kg",
    "actuator_d": "m", "link_density": "kg/m", "g": "m/s^2"}


def _c_default() -> Any:
    c = ffi.new("rps3_design *")
    lib.rps3_design_default(c)
    return c


_DEF = _c_default()


def _d(name: str) -> Any:
    return field(default=float(getattr(_DEF, name)))


@dataclass(frozen=True)
class Design:
    """A design of the manipulator, the library's rps3_design: the
    geometry of Table II, the joint limits and a mass model (links: an
    actuator body at ``actuator_d`` from the pin and a uniform rod of
    ``link_density`` from the pin to ``l_max``; include/rps3.h).

    Every field left out takes the library's default: Table II (R =
    0.2286 m, rho = 0.5, M = 0.18 kg, links of 0.09 kg at d = 0.1524 m),
    the stroke [R, 2 R] (the paper gives none; it holds the helix), the
    pin range [0, pi], ball joints to pi/4 from the platform normal, no
    interference check, no payload.

    Raises:
        ValueError: naming the field, for a value out of range or a rule
            between fields broken (l_max > l_min, theta_max > theta_min).
        TypeError: naming the field, for a value that is not a real number.
    """

    R: float = _d("R")                          #: base radius [m]
    rho: float = _d("rho")                      #: r / R [-]
    l_min: float = _d("l_min")                  #: shortest link length [m]
    l_max: float = _d("l_max")                  #: longest link length [m]
    theta_min: float = _d("theta_min")          #: pin range, from [rad]
    theta_max: float = _d("theta_max")          #: pin range, to [rad]
    ball_max: float = _d("ball_max")            #: ball joint cone half-angle [rad]
    link_radius: float = _d("link_radius")      #: link capsule radius, 0: off [m]
    M: float = _d("M")                          #: platform mass [kg]
    payload: float = _d("payload")              #: payload mass [kg]
    payload_height: float = _d("payload_height")  #: payload above the platform [m]
    actuator_mass: float = _d("actuator_mass")  #: actuator body mass [kg]
    actuator_d: float = _d("actuator_d")        #: its distance from the pin [m]
    link_density: float = _d("link_density")    #: rod mass per length [kg/m]
    g: float = _d("g")                          #: gravity [m/s^2]

    def __post_init__(self) -> None:
        for name in UNITS:
            object.__setattr__(self, name, real_number(
                getattr(self, name), name, finite=False))
        chk = ffi.new("rps3_check *")
        if lib.rps3_design_validate(self._c(), chk) != lib.RPS3_OK:
            raise ValueError(f"{_field_name(chk.field)}: {text(chk.msg)}")

    def _c(self) -> Any:
        c = ffi.new("rps3_design *")
        for name in UNITS:
            setattr(c, name, getattr(self, name))
        return c

    def replace(self, **changes: Any) -> Design:
        """A copy with the fields given changed (validated again)."""
        unknown = set(changes) - set(UNITS)
        if unknown:
            raise TypeError(f"{sorted(unknown)[0]}: not a field of Design; "
                            f"fields: {', '.join(UNITS)}")
        return dataclasses.replace(self, **changes)

    @property
    def r(self) -> float:
        """Platform radius rho R [m]."""
        return self.rho * self.R

    @property
    def stroke_ratio(self) -> float:
        """l_max / l_min [-] (inf for l_min = 0)."""
        return self.l_max / self.l_min if self.l_min > 0 else math.inf

    def masses(self) -> dict[str, float]:
        """The model's link numbers of the mass model: m [kg], d [m],
        link_Ic [kg m^2] (rps3_design_model)."""
        m = self._model_c()
        return {"m": float(m.m), "d": float(m.d), "link_Ic": float(m.link_Ic)}

    def _model_c(self) -> Any:
        m = ffi.new("rps3_model *")
        err = ffi.new("char[]", 256)
        if lib.rps3_design_model(self._c(), m, err, 256) != lib.RPS3_OK:
            raise ValueError(text(err))
        return m

    def model(self, **options: Any) -> Model:
        """The manipulator of this design as an rps3.Model (the links of
        the mass model, the payload as a point mass on the platform
        normal), e.g. for rps3.view.draw.  options: Model's keyword
        arguments (effects, method, ...)."""
        c = self._model_c()
        kw: dict[str, Any] = dict(R=self.R, rho=self.rho, M=self.M,
                                  m=float(c.m), d=float(c.d),
                                  link_Ic=float(c.link_Ic), g=self.g)
        if self.payload > 0:
            kw["payload"] = {"mass": self.payload,
                             "com": [0.0, 0.0, self.payload_height],
                             "inertia": [0.0, 0.0, 0.0]}
            kw["effects"] = [*Model().effects, "payload"]
        kw.update(options)
        return Model(**kw)


def _field_name(fid: int) -> str:
    row = lib.rps3_design_field(int(fid))
    return text(row.name) if row != ffi.NULL else "design"


# ------------------------------------------------------------------- grid

#: the pose coordinates of a grid, in the library's order, and their units
COORDS: tuple[str, ...] = ("alpha", "beta", "z_c")
_COORD_UNITS = {"alpha": "rad", "beta": "rad", "z_c": "m"}


@dataclass(frozen=True)
class Grid:
    """A regular, cell-centred grid of poses (rps3_design_grid): node j of
    coordinate k at lo[k] + (j + 1/2) (hi[k] - lo[k]) / n[k]; poses in the
    order alpha fastest, then beta, then z_c."""

    lo: tuple[float, float, float]   #: lower bounds: alpha, beta [rad], z_c [m]
    hi: tuple[float, float, float]   #: upper bounds
    n: tuple[int, int, int]          #: nodes per coordinate

    def _c(self) -> Any:
        c = ffi.new("rps3_design_grid *")
        for k in range(3):
            c.lo[k], c.hi[k], c.n[k] = self.lo[k], self.hi[k], self.n[k]
        return c

    def axis(self, name: str) -> FloatArray:
        """The nodes of coordinate name ("alpha", "beta" or "z_c")."""
        k = COORDS.index(name)
        j = np.arange(self.n[k]) + 0.5
        return self.lo[k] + j * (self.hi[k] - self.lo[k]) / self.n[k]

    @property
    def size(self) -> int:
        """Number of poses."""
        return int(np.prod(self.n))

    @property
    def cell_volume(self) -> float:
        """Volume of one cell [m rad^2]."""
        return float(np.prod([(h - lo) / k for lo, h, k in
                              zip(self.lo, self.hi, self.n)]))

    @property
    def poses(self) -> FloatArray:
        """Every pose, (size, 3), alpha fastest."""
        z, b, a = np.meshgrid(self.axis("z_c"), self.axis("beta"),
                              self.axis("alpha"), indexing="ij")
        return np.stack([a.ravel(), b.ravel(), z.ravel()], axis=1)


def _range(value: Any, name: str) -> tuple[float, float]:
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected (lower, upper), got {value!r}") from None
    lo = real_number(lo, f"{name}[0]")
    hi = real_number(hi, f"{name}[1]")
    if lo > hi:
        raise ValueError(f"{name}: inverted range, lower {lo!r} above upper {hi!r}")
    if lo == hi:
        raise ValueError(f"{name}: empty range, lower = upper = {lo!r}")
    return lo, hi


def grid(design: Design | None = None, *, alpha: Sequence[float] | None = None,
         beta: Sequence[float] | None = None, z: Sequence[float] | None = None,
         n: int | Sequence[int] | None = None) -> Grid:
    """A grid of poses (alpha, beta, z_c) to evaluate designs on.

    Args:
        design: the defaults are this design's (rps3_design_grid_default:
            alpha in [-pi, pi], beta in [0, pi/3], z_c in [0, 2 R]);
            None: Table II's.
        alpha, beta: (lower, upper) [rad].
        z: (lower, upper) of z_c [m].
        n: nodes per coordinate, one int for all three or three (default
            10 each).

    Raises:
        ValueError: naming the coordinate, for an inverted or empty range
            or a count below 1.
    """
    c = ffi.new("rps3_design_grid *")
    lib.rps3_design_grid_default(design._c() if design is not None else ffi.NULL, c)
    lo = [float(c.lo[k]) for k in range(3)]
    hi = [float(c.hi[k]) for k in range(3)]
    counts = [int(c.n[k]) for k in range(3)]
    for k, (name, value) in enumerate((("alpha", alpha), ("beta", beta), ("z", z))):
        if value is not None:
            lo[k], hi[k] = _range(value, name)
    if n is not None:
        if isinstance(n, (int, np.integer)):
            given = [n] * 3
        else:
            try:
                given = list(n)
            except TypeError:
                raise ValueError(f"n: expected one count or three, got {n!r}") from None
        if len(given) != 3:
            raise ValueError(f"n: expected one count or three, got {n!r}")
        for k, v in enumerate(given):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                raise ValueError(f"n: expected counts >= 1, got {n!r}")
            counts[k] = int(v)
    return Grid(tuple(lo), tuple(hi), tuple(counts))  # type: ignore[arg-type]


# ---------------------------------------------------------------- workspace

_LOCAL = threading.local()


def _ws() -> Any:
    # one library workspace per thread, kept for the thread's life: an
    # optimisation evaluates thousands of designs
    w = getattr(_LOCAL, "ws", None)
    if w is None:
        out = ffi.new("rps3_design_ws **")
        status = lib.rps3_design_ws_alloc(out)
        if status != lib.RPS3_OK:
            raise MemoryError("rps3_design_ws_alloc: out of memory")
        w = ffi.gc(out[0], lib.rps3_design_ws_free)
        _LOCAL.ws = w
    return w


@dataclass(frozen=True)
class Options:
    """How the indices are evaluated (rps3_design_opts)."""

    lti_good: float = 0.7     #: good transmission: LTI >= lti_good [-]
    length: float = 0.0       #: L of the homogeneous condition number, 0: r [m]
    cond_sing: float = 1e8    #: singular above this condition number [-]

    def _c(self) -> Any:
        c = ffi.new("rps3_design_opts *")
        lib.rps3_design_opts_default(c)
        c.lti_good = real_number(self.lti_good, "lti_good")
        c.length = real_number(self.length, "length")
        c.cond_sing = real_number(self.cond_sing, "cond_sing")
        return c


#: names of the reachability flags, bit k = 1 << k (rps3_design_flag_name)
FLAGS: tuple[str, ...] = tuple(text(lib.rps3_design_flag_name(k))
                               for k in range(lib.RPS3_DESIGN_NFLAG))


@dataclass(frozen=True)
class Summary:
    """A design's summary over the reachable poses of a set (zeros when
    none is reachable: ``empty``)."""

    n: int                  #: poses evaluated
    nreach: int             #: reachable poses
    reach_fraction: float   #: nreach / n [-]
    volume: float           #: nreach times the cell volume [m rad^2]
    gti: float              #: global transmission index, mean LTI [-]
    good_fraction: float    #: fraction of reachable poses with LTI >= lti_good [-]
    lti_min: float          #: least LTI [-]
    cond_h_max: float       #: largest homogeneous condition number [-]
    trans_max: float        #: largest force transmission [-]
    xc_max: float           #: largest |x_c| [m]
    yc_max: float           #: largest |y_c| [m]
    spin_max: float         #: largest |spin| [rad]
    l_lo: float             #: shortest link length used [m]
    l_hi: float             #: longest link length used [m]
    nflag: dict[str, int]   #: poses with each flag set, by flag name

    @property
    def empty(self) -> bool:
        """No pose is reachable."""
        return self.nreach == 0


_SUMMARY_UNITS = {"n": "1", "nreach": "1", "reach_fraction": "1",
                  "volume": "m rad^2", "gti": "1", "good_fraction": "1",
                  "lti_min": "1", "cond_h_max": "1", "trans_max": "1",
                  "xc_max": "m", "yc_max": "m", "spin_max": "rad",
                  "l_lo": "m", "l_hi": "m"}


def _summary(s: Any) -> Summary:
    vals: dict[str, Any] = {k: (int(getattr(s, k)) if k in ("n", "nreach")
                                else float(getattr(s, k)))
                            for k in _SUMMARY_UNITS}
    vals["nflag"] = {name: int(s.nflag[k]) for k, name in enumerate(FLAGS)}
    return Summary(**vals)


def _poses(where: Grid | ArrayLike, cell_volume: float | None
           ) -> tuple[FloatArray, float, Grid | None]:
    if isinstance(where, Grid):
        if cell_volume is not None:
            raise ValueError("cell_volume: a grid has its own")
        return np.ascontiguousarray(where.poses.T), where.cell_volume, where
    p, _ = points3(where, "poses")
    cv = 0.0 if cell_volume is None else real_number(cell_volume, "cell_volume", lo=0.0)
    if p.shape[1] == 0:
        raise ValueError("poses: no pose given")
    return p, cv, None


_PER_POSE = {"l": 3, "theta": 3, "ball": 3, "clearance": 1, "lti": 1,
             "oti": 1, "cti": 1, "cond_h": 1, "transmission": 1, "c": 3,
             "spin": 1}


def _eval(design: Design, p: FloatArray, cell: float, opts: Options | None,
          per_pose: bool) -> tuple[Summary, dict[str, np.ndarray], int]:
    """The library's evaluation of the (3, n) poses p: the summary, the
    per-pose arrays (component-major; flags alone unless per_pose) and
    the status (RPS3_OK or RPS3_EEMPTY)."""
    if not isinstance(design, Design):
        raise TypeError(f"design: expected an rps3.design.Design, got "
                        f"{type(design).__name__}")
    n = p.shape[1]
    w = _ws()
    arrays: dict[str, np.ndarray] = {"flags": np.empty(n, np.int32)}
    out = ffi.new("rps3_design_out *")
    keep = [buf(arrays["flags"], "int[]")]
    out.flags = keep[0]
    if per_pose:
        for name, rows in _PER_POSE.items():
            arrays[name] = np.empty((rows, n)) if rows > 1 else np.empty(n)
            keep.append(buf(arrays[name]))
            setattr(out, name, keep[-1])
    s = ffi.new("rps3_design_summary *")
    status = lib.rps3_design_eval(w, design._c(), (opts or Options())._c(),
                                  n, buf(p), cell, out, s)
    if status not in (lib.RPS3_OK, lib.RPS3_EEMPTY):
        raise error(status, text(w.err.msg))
    return _summary(s), arrays, int(status)


def summarise(design: Design, where: Grid | ArrayLike, *,
              cell_volume: float | None = None,
              options: Options | None = None) -> Summary:
    """The summary of design over a grid or poses, without the per-pose
    arrays (the fast path of the optimisers).

    Args:
        design: the design.
        where: a Grid, or an (n, 3) array of poses (alpha, beta, z_c).
        cell_volume: with poses, the volume each stands for [m rad^2]
            (default 0: volume 0).
        options: how the indices are evaluated.
    """
    if isinstance(where, Grid):
        if cell_volume is not None:
            raise ValueError("cell_volume: a grid has its own")
        if not isinstance(design, Design):
            raise TypeError(f"design: expected an rps3.design.Design, got "
                            f"{type(design).__name__}")
        # the library walks the grid itself: no array of poses
        w = _ws()
        flags = np.empty(where.size, np.int32)
        out = ffi.new("rps3_design_out *")
        out.flags = buf(flags, "int[]")
        s = ffi.new("rps3_design_summary *")
        status = lib.rps3_design_eval_grid(w, design._c(), (options or Options())._c(),
                                           where._c(), out, s)
        if status not in (lib.RPS3_OK, lib.RPS3_EEMPTY):
            raise error(status, text(w.err.msg))
        return _summary(s)
    p, cell, _ = _poses(where, cell_volume)
    return _eval(design, p, cell, options, False)[0]


def evaluate(design: Design, where: Grid | ArrayLike | None = None, *,
             cell_volume: float | None = None,
             options: Options | None = None) -> xr.Dataset:
    """The per-pose indices of design and their summary, as an
    xarray.Dataset (every variable with a ``units`` attribute).

    Args:
        design: the design.
        where: a Grid (default ``grid(design)``): the per-pose variables
            have the dimensions (z_c, beta, alpha); or an (n, 3) array of
            poses: dimension ``pose``, with alpha, beta, z_c as
            coordinates along it.
        cell_volume: with poses, the volume each stands for [m rad^2].
        options: how the indices are evaluated.

    Returns:
        Per pose: ``flags`` (bits, names in ``FLAGS``), ``reachable``,
        ``l``, ``theta``, ``ball`` (with a dimension ``link``),
        ``clearance``, ``lti``, ``oti``, ``cti``, ``cond_h``,
        ``transmission``, ``x_c``, ``y_c``, ``spin``.  The summary as 0-d
        variables: ``n``, ``nreach``, ``reach_fraction``, ``volume``,
        ``gti``, ``good_fraction``, ``lti_min``, ``cond_h_max``,
        ``trans_max``, ``xc_max``, ``yc_max``, ``spin_max``, ``l_lo``,
        ``l_hi`` and ``nflag`` (dimension ``flag``).  ``attrs["empty"]``
        is 1 when no pose is reachable (the summary is then zeros).

    Raises:
        ValueError, TypeError: naming the argument.
    """
    import xarray as xr

    if where is None:
        where = grid(design)
    p, cell, gr = _poses(where, cell_volume)
    s, a, status = _eval(design, p, cell, options, True)
    if gr is not None:
        dims: tuple[str, ...] = ("z_c", "beta", "alpha")
        shape: tuple[int, ...] = (gr.n[2], gr.n[1], gr.n[0])
        coords: dict[str, Any] = {name: ((name,), gr.axis(name),
                                         {"units": _COORD_UNITS[name]})
                                  for name in COORDS}
    else:
        dims, shape = ("pose",), (p.shape[1],)
        coords = {name: (("pose",), p[k], {"units": _COORD_UNITS[name]})
                  for k, name in enumerate(COORDS)}
    coords["link"] = (("link",), np.arange(1, 4), {"units": "1"})
    coords["flag"] = (("flag",), list(FLAGS), {})

    def grid_of(x: np.ndarray) -> np.ndarray:
        return x.reshape(shape)

    def links(x: np.ndarray) -> np.ndarray:
        return np.moveaxis(x.reshape((3, *shape)), 0, -1)

    units = {"l": "m", "theta": "rad", "ball": "rad", "clearance": "m",
             "lti": "1", "oti": "1", "cti": "1", "cond_h": "1",
             "transmission": "1", "spin": "rad"}
    data: dict[str, Any] = {
        "flags": (dims, grid_of(a["flags"]), {"units": "1", "flag_names":
                                              " ".join(FLAGS)}),
        "reachable": (dims, grid_of(a["flags"] == 0), {"units": "1"}),
        "x_c": (dims, grid_of(a["c"][0]), {"units": "m"}),
        "y_c": (dims, grid_of(a["c"][1]), {"units": "m"})}
    for name in ("l", "theta", "ball"):
        data[name] = ((*dims, "link"), links(a[name]), {"units": units[name]})
    for name in ("clearance", "lti", "oti", "cti", "cond_h", "transmission",
                 "spin"):
        data[name] = (dims, grid_of(a[name]), {"units": units[name]})
    for name, unit in _SUMMARY_UNITS.items():
        data[name] = ((), getattr(s, name), {"units": unit})
    data["nflag"] = (("flag",), [s.nflag[f] for f in FLAGS], {"units": "1"})
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update({"empty": int(status == lib.RPS3_EEMPTY),
                     "cell_volume": cell, "cell_volume_units": "m rad^2",
                     **{f"design_{k}": getattr(design, k) for k in UNITS}})
    return ds


# ------------------------------------------------------------------- task

@dataclass(frozen=True)
class Task:
    """What a task asks of a design's actuators (rps3_design_task), per
    link (leading axis 3)."""

    F_peak: FloatArray     #: max_t |F_i| [N]
    F_rms: FloatArray      #: RMS of F_i over the samples [N]
    P_peak: FloatArray     #: max_t |F_i dl_i| [W]
    v_peak: FloatArray     #: max_t |dl_i| [m/s]
    l_lo: FloatArray       #: shortest length of each link [m]
    l_hi: FloatArray       #: longest [m]
    lti_min: float         #: least LTI along the task [-]
    nsamples: int          #: samples evaluated

    @property
    def peak_force(self) -> float:
        """The largest actuator force of any link [N]."""
        return float(np.max(self.F_peak))

    @property
    def rms_force(self) -> float:
        """The largest RMS force of any link [N]."""
        return float(np.max(self.F_rms))

    @property
    def peak_power(self) -> float:
        """The largest actuator power of any link [W]."""
        return float(np.max(self.P_peak))


def _spec(trajectory: Trajectory | Spec) -> tuple[Any, int | None]:
    from rps3.trajectory import Spec, Trajectory
    if isinstance(trajectory, Trajectory):
        if trajectory.spec is None:
            raise TypeError("trajectory: has no library description (spec)")
        return trajectory.spec.c, len(trajectory.t)
    if isinstance(trajectory, Spec):
        return trajectory.c, None
    raise TypeError(f"trajectory: expected an rps3.trajectory.Trajectory, "
                    f"got {type(trajectory).__name__}")


def _task_c(design: Design, tr: Any, samples: int, link_mass: bool,
            opts: Options | None) -> tuple[int, Any, str]:
    w = _ws()
    res = ffi.new("rps3_design_task *")
    status = lib.rps3_design_task_eval(
        w, design._c(), (opts or Options())._c(), tr, samples,
        lib.RPS3_DESIGN_LINK_MASS if link_mass else lib.RPS3_DESIGN_NO_LINK_MASS,
        res)
    return int(status), res, text(w.err.msg)


def _task_result(res: Any) -> Task:
    def v(name: str) -> FloatArray:
        return np.array([float(getattr(res, name)[i]) for i in range(3)])
    return Task(F_peak=v("F_peak"), F_rms=v("F_rms"), P_peak=v("P_peak"),
                v_peak=v("v_peak"), l_lo=v("l_lo"), l_hi=v("l_hi"),
                lti_min=float(res.lti_min), nsamples=int(res.nsamples))


def _samples(samples: int | None, default: int | None) -> int:
    n = samples if samples is not None else (default or 201)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise ValueError(f"samples: expected an integer >= 2, got {samples!r}")
    return int(n)


def task(design: Design, trajectory: Trajectory | Spec, *,
         samples: int | None = None, link_mass: bool = True,
         options: Options | None = None) -> Task:
    """The actuator requirements of a task: the trajectory sampled at
    equally spaced times over its span, the forces by the library's batch
    inverse dynamics with the design's model (the payload included when
    design.payload > 0).

    Args:
        design: the design.
        trajectory: an rps3.trajectory.Trajectory (or its ``spec``).
        samples: number of samples (default: as many as the Trajectory
            has, 201 for a Spec).
        link_mass: False leaves the links' gravity and inertia out (the
            paper's case 1).
        options: how the LTI is evaluated.

    Raises:
        rps3.errors.ReachError: a sample is outside the design's
            workspace; the message names its time and why (the limits
            crossed), ``exc.result`` holds the requirements of the samples
            before it.
        ValueError: naming the argument (a trajectory the design's model
            refuses, samples < 2).
    """
    tr, n_default = _spec(trajectory)
    n = _samples(samples, n_default)
    status, res, msg = _task_c(design, tr, n, link_mass, options)
    if status == lib.RPS3_EREACH:
        exc = ReachError(f"trajectory: outside the design's workspace: {msg}",
                         status)
        exc.result = _task_result(res)  # type: ignore[attr-defined]
        raise exc
    if status != lib.RPS3_OK:
        raise error(status, f"trajectory: {msg}")
    return _task_result(res)


# ------------------------------------------------------------ optimisation

#: an optimiser stopped without meeting its tolerances, or returned a
#: design that breaks a constraint (rps3.errors.ConvergenceWarning)
ConvergenceWarning = _errors.ConvergenceWarning


#: what can be optimised: name -> (+1 minimised, -1 maximised, unit, needs)
OBJECTIVES: dict[str, tuple[int, str, str]] = {
    "peak_force": (1, "N", "task"), "rms_force": (1, "N", "task"),
    "peak_power": (1, "W", "task"), "volume": (-1, "m rad^2", "grid"),
    "gti": (-1, "1", "grid"), "good_fraction": (-1, "1", "grid")}

#: the design variables beyond Design's fields: l_max = stroke_ratio l_min
DERIVED = ("stroke_ratio",)


def _variables(variables: Mapping[str, Sequence[float]]) -> tuple[
        tuple[str, ...], FloatArray, FloatArray]:
    if not isinstance(variables, Mapping) or not variables:
        raise ValueError("variables: expected a mapping of design variables to "
                         f"(lower, upper) bounds, got {variables!r}")
    names = tuple(variables)
    for name in names:
        if name not in UNITS and name not in DERIVED:
            raise ValueError(f"variables[{name!r}]: not a design variable; one of "
                             f"{', '.join([*UNITS, *DERIVED])}")
    if "stroke_ratio" in names and "l_max" in names:
        raise ValueError("variables['stroke_ratio']: give stroke_ratio or l_max, "
                         "not both")
    bounds = [_range(variables[k], f"variables[{k!r}]") for k in names]
    return names, np.array([b[0] for b in bounds]), np.array([b[1] for b in bounds])


def _apply(base: Design, names: tuple[str, ...], values: FloatArray) -> Design:
    kw = {k: float(v) for k, v in zip(names, values)}
    ratio = kw.pop("stroke_ratio", None)
    if ratio is not None:
        kw["l_max"] = ratio * kw.get("l_min", base.l_min)
    return base.replace(**kw)


def _reach_violation(ds: Design, poses: FloatArray, opts: Options | None
                     ) -> tuple[float, float]:
    """How far the poses (3, n) are outside ds's workspace, at the worst
    pose: the largest excess over a limit, lengths relative to l_max and
    angles in radians (<= 0: every pose reachable; a pose that does not
    assemble or is singular counts 1); and the least LTI among them."""
    s, a, _ = _eval(ds, poses, 0.0, opts, True)
    flags = a["flags"]
    hard = (flags & (lib.RPS3_DESIGN_ASSEMBLY | lib.RPS3_DESIGN_SINGULAR)) != 0
    with np.errstate(invalid="ignore"):
        ex = [np.max((ds.l_min - a["l"]) / ds.l_max, axis=0),
              np.max((a["l"] - ds.l_max) / ds.l_max, axis=0),
              np.max(ds.theta_min - a["theta"], axis=0),
              np.max(a["theta"] - ds.theta_max, axis=0),
              np.max(a["ball"] - ds.ball_max, axis=0)]
        if ds.link_radius > 0:
            ex.append(-a["clearance"] / ds.l_max)
        excess = np.max(np.stack(ex), axis=0)
    excess = np.where(hard, 1.0, excess)
    # a pose the library flags must count as outside, whatever the rounding
    excess = np.where((flags != 0) & (excess <= 0), 1e-9, excess)
    lti = a["lti"][~hard]
    return float(np.max(excess)), float(np.min(lti)) if lti.size else 0.0


@dataclass
class _Problem:
    """A design problem: variables, objectives and constraints, evaluated
    design by design."""

    names: tuple[str, ...]
    lo: FloatArray
    hi: FloatArray
    objectives: tuple[str, ...]
    base: Design
    trajectory: Any = None
    samples: int = 201
    grid: Grid | None = None
    covers: FloatArray | None = None
    volume_min: float | None = None
    force_max: float | None = None
    lti_min: float | None = None
    options: Options | None = None
    platform_mass: str = "fixed"
    reached_task: int = 0   # designs evaluated that follow the task

    @property
    def constraint_names(self) -> tuple[str, ...]:
        out = []
        if self.trajectory is not None:
            out.append("task_reach")
        if self.covers is not None:
            out.append("covers")
        for name in ("volume_min", "force_max", "lti_min"):
            if getattr(self, name) is not None:
                out.append(name)
        return tuple(out)

    def design(self, x: FloatArray) -> Design:
        ds = _apply(self.base, self.names, self.lo + np.asarray(x) * (self.hi - self.lo))
        if self.platform_mass == "area":
            # a plate of the base design's areal density: M grows as r^2
            ds = ds.replace(M=self.base.M * (ds.r / self.base.r) ** 2)
        return ds

    def values(self, x: FloatArray) -> tuple[dict[str, float], dict[str, float]]:
        """Objectives (natural units and sense) and constraint values (<= 0
        satisfied) of the scaled point x; an invalid design has NaN
        objectives and every constraint at 1."""
        try:
            ds = self.design(x)
        except ValueError:
            return ({k: math.nan for k in self.objectives},
                    {k: 1.0 for k in self.constraint_names})
        obj: dict[str, float] = {}
        con: dict[str, float] = {}
        lti_floor = math.inf
        need_grid = self.volume_min is not None or any(
            OBJECTIVES[k][2] == "grid" for k in self.objectives)
        if need_grid:
            s = summarise(ds, self.grid if self.grid is not None else grid(ds),
                          options=self.options)
            for k in self.objectives:
                if OBJECTIVES[k][2] == "grid":
                    obj[k] = float(getattr(s, k))
            if self.volume_min is not None:
                con["volume_min"] = 1.0 - s.volume / self.volume_min
        if self.trajectory is not None:
            tr = self.trajectory
            try:
                traj_poses = tr.eval(np.linspace(0.0, tr.duration, self.samples),
                                     ds.model()).pose
            except ValueError:
                # a task this design's model refuses (e.g. a helix wider
                # than the platform allows): it cannot follow it
                for k in self.objectives:
                    if OBJECTIVES[k][2] == "task":
                        obj[k] = math.nan
                con["task_reach"] = 1.0
                if self.force_max is not None:
                    con["force_max"] = 1.0
                lti_floor = 0.0
                traj_poses = None
        if self.trajectory is not None and traj_poses is not None:
            tr = self.trajectory
            viol, lti_t = _reach_violation(ds, np.ascontiguousarray(traj_poses.T),
                                           self.options)
            status, res, _ = _task_c(ds, tr.c, self.samples, True, self.options)
            t = _task_result(res)
            if status != lib.RPS3_OK:
                viol = max(viol, 1e-9)
            else:
                self.reached_task += 1
            con["task_reach"] = viol
            lti_floor = min(lti_floor, lti_t)
            vals = {"peak_force": t.peak_force, "rms_force": t.rms_force,
                    "peak_power": t.peak_power}
            for k in self.objectives:
                if OBJECTIVES[k][2] == "task":
                    obj[k] = vals[k]
            if self.force_max is not None:
                con["force_max"] = t.peak_force / self.force_max - 1.0
        if self.covers is not None:
            viol, lti_c = _reach_violation(ds, self.covers, self.options)
            con["covers"] = viol
            lti_floor = min(lti_floor, lti_c)
        if self.lti_min is not None:
            con["lti_min"] = self.lti_min - lti_floor
        return obj, {k: con[k] for k in self.constraint_names}

    def minimised(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Objectives all minimised (maximised ones negated; NaN, of an
        invalid design, as a large penalty) and the constraints."""
        obj, con = self.values(x)
        f = np.array([OBJECTIVES[k][0] * obj[k] for k in self.objectives])
        f = np.where(np.isfinite(f), f, 1e30)
        return f, np.array([con[k] for k in self.constraint_names])


def _problem(variables: Mapping[str, Sequence[float]], objectives: Sequence[str],
             base: Design | None, trajectory: Any, samples: int | None,
             grid_: Grid | None, covers: ArrayLike | None,
             volume_min: float | None, force_max: float | None,
             lti_min: float | None, options: Options | None,
             platform_mass: str = "fixed") -> _Problem:
    names, lo, hi = _variables(variables)
    if platform_mass not in ("fixed", "area"):
        raise ValueError(f"platform_mass: {platform_mass!r} is not 'fixed' or 'area'")
    if platform_mass == "area" and "M" in names:
        raise ValueError("variables['M']: with platform_mass='area' M follows r")
    base = Design() if base is None else base
    if not isinstance(base, Design):
        raise TypeError(f"base: expected a Design, got {type(base).__name__}")
    for k in objectives:
        if k not in OBJECTIVES:
            raise ValueError(f"objective: {k!r} is not one of {', '.join(OBJECTIVES)}")
    if len(set(objectives)) != len(objectives):
        raise ValueError(f"objectives: {list(objectives)} names one twice")
    needs_task = [k for k in objectives if OBJECTIVES[k][2] == "task"]
    if (needs_task or force_max is not None) and trajectory is None:
        what = needs_task[0] if needs_task else "force_max"
        raise ValueError(f"trajectory: {what} needs a task trajectory")
    # every bound must make a valid design with the others mid-range
    mid = (lo + hi) / 2
    for j, name in enumerate(names):
        for side, v in (("lower", float(lo[j])), ("upper", float(hi[j]))):
            x = mid.copy()
            x[j] = v
            if name == "stroke_ratio" and v <= 1:
                raise ValueError(f"variables['stroke_ratio']: {side} bound {v!r} "
                                 "must be > 1 (l_max above l_min: a stroke > 0)")
            try:
                _apply(base, names, x)
            except ValueError as e:
                raise ValueError(f"variables[{name!r}]: the {side} bound {v!r} "
                                 f"makes no valid design: {e}") from None
    tr = None
    if trajectory is not None:
        tr_c, n_default = _spec(trajectory)
        from rps3.trajectory import Spec
        tr = trajectory.spec if not isinstance(trajectory, Spec) else trajectory
        samples = _samples(samples, n_default)
    cov = None
    if covers is not None:
        cov, _ = points3(covers, "covers")
        if cov.shape[1] == 0:
            raise ValueError("covers: no pose given")
    checks: dict[str, float | None] = {}
    for name, value in (("volume_min", volume_min), ("force_max", force_max)):
        checks[name] = None if value is None else real_number(value, name, lo=0.0,
                                                              lo_open=True)
    lti = None if lti_min is None else real_number(lti_min, "lti_min", lo=0.0)
    if lti is not None and lti > 1:
        raise ValueError(f"lti_min: must be <= 1 (the LTI is in [0, 1]), got {lti!r}")
    return _Problem(names, lo, hi, tuple(objectives), base, tr, samples or 201,
                    grid_, cov, checks["volume_min"], checks["force_max"], lti,
                    options, platform_mass)


@dataclass(frozen=True)
class Optimum:
    """A constrained optimum found by NLopt."""

    design: Design                  #: the design found
    objective: str                  #: what was optimised
    value: float                    #: its value [the objective's unit]
    variables: dict[str, float]     #: the design variables' values
    constraints: dict[str, float]   #: each constraint's value, <= 0 met
    feasible: bool                  #: every constraint met (within ctol)
    converged: bool                 #: NLopt met a stopping tolerance
    status: str                     #: NLopt's result, e.g. "XTOL_REACHED"
    algorithm: str                  #: "COBYLA" or "AUGLAG"
    nevals: int                     #: designs evaluated
    seed: int                       #: seed of the starting sample
    problem: _Problem = field(repr=False, compare=False)


def _lhs(n: int, k: int, seed: int) -> FloatArray:
    """A Latin hypercube of n points in [0, 1]^k."""
    rng = np.random.default_rng(seed)
    u = (np.argsort(rng.random((k, n)), axis=1).T + rng.random((n, k))) / n
    return np.asarray(u)


def optimise(variables: Mapping[str, Sequence[float]],
             objective: str = "peak_force", *, base: Design | None = None,
             trajectory: Trajectory | Spec | None = None,
             samples: int | None = None, grid: Grid | None = None,
             covers: ArrayLike | None = None, volume_min: float | None = None,
             force_max: float | None = None, lti_min: float | None = None,
             algorithm: str = "COBYLA", x0: Mapping[str, float] | None = None,
             prescan: int = 16, seed: int = 1, xtol_rel: float = 1e-4,
             ftol_rel: float = 1e-8, maxeval: int = 400, ctol: float = 1e-9,
             platform_mass: str = "fixed", options: Options | None = None) -> Optimum:
    """The design that minimises (or maximises) one objective under
    constraints, by NLopt's derivative-free COBYLA (or an augmented
    Lagrangian around BOBYQA, "AUGLAG").

    Args:
        variables: design variables and their bounds, e.g. ``{"rho": (0.3,
            0.9), "R": (0.15, 0.3)}``: fields of Design, or
            ``stroke_ratio`` (l_max = stroke_ratio l_min).
        objective: one of OBJECTIVES: ``peak_force``, ``rms_force``,
            ``peak_power`` (of the task, minimised), ``volume``, ``gti``,
            ``good_fraction`` (over the grid, maximised).
        base: the design the variables change (default Design()).
        trajectory: the task (a Trajectory, or its spec); the design must
            follow it (constraint ``task_reach``).
        samples: samples of the task (default: the Trajectory's).
        grid: the poses of volume, gti, good_fraction (default: each
            design's ``grid(design)``).
        covers: (n, 3) poses every design must reach (e.g. the reachable
            poses of Table II's design: "at least its workspace").
        volume_min: least workspace volume over grid [m rad^2].
        force_max: largest peak actuator force of the task [N].
        lti_min: least LTI along the task and over covers [-].
        algorithm: "COBYLA" or "AUGLAG".
        x0: the starting design variables; default: the best of a Latin
            hypercube of ``prescan`` designs drawn with ``seed``.
        xtol_rel, ftol_rel, maxeval: NLopt's stopping rules (relative to
            the variables scaled to [0, 1]).
        ctol: constraint tolerance.
        platform_mass: "fixed" (base.M for every design) or "area" (a
            plate of base's areal density: M = base.M (r / base.r)^2).

    Returns:
        Optimum.  When NLopt stops without meeting xtol_rel or ftol_rel
        (evaluation budget, roundoff, failure) ``converged`` is False,
        and when the design breaks a constraint ``feasible`` is False;
        either way a ConvergenceWarning says so.

    Raises:
        ValueError: naming the argument: an unknown or duplicated
            variable, inverted or empty bounds, a bound that makes no valid
            design (a negative or empty stroke), a constraint out of range,
            a task that no design tried can follow (``trajectory``).
    """
    if algorithm not in ("COBYLA", "AUGLAG"):
        raise ValueError(f"algorithm: {algorithm!r} is not COBYLA or AUGLAG")
    for name, v, least in (("maxeval", maxeval, 1), ("prescan", prescan, 1),
                           ("seed", seed, 0)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < least:
            raise ValueError(f"{name}: expected an integer >= {least}, got {v!r}")
    for name, fv in (("xtol_rel", xtol_rel), ("ftol_rel", ftol_rel)):
        real_number(fv, name, lo=0.0, lo_open=True)
    ctol = real_number(ctol, "ctol", lo=0.0)
    pb = _problem(variables, (objective,), base, trajectory, samples, grid,
                  covers, volume_min, force_max, lti_min, options, platform_mass)
    n = len(pb.names)

    def key(f: float, g: FloatArray) -> tuple[float, float]:
        viol = float(np.max(g)) if g.size else -math.inf
        return (max(viol, 0.0) if viol > ctol else 0.0, f)

    if x0 is not None:
        if set(x0) != set(pb.names):
            raise ValueError(f"x0: expected values of {list(pb.names)}, got "
                             f"{sorted(x0)}")
        start = np.array([(real_number(x0[k], f"x0[{k!r}]") - pb.lo[j])
                          / (pb.hi[j] - pb.lo[j]) for j, k in enumerate(pb.names)])
        if np.any(start < 0) or np.any(start > 1):
            raise ValueError(f"x0: {dict(x0)} is outside the variables' bounds")
    else:
        best = None
        for x in _lhs(prescan, n, seed):
            f, g = pb.minimised(x)
            if best is None or key(f[0], g) < best[0]:
                best = (key(f[0], g), x)
        assert best is not None
        start = best[1]
    loc = _optimise.nlopt_minimise(
        lambda x: (lambda fg: (float(fg[0][0]), fg[1]))(pb.minimised(x)),
        len(pb.constraint_names), start, algorithm=algorithm,
        xtol_rel=xtol_rel, ftol_rel=ftol_rel, maxeval=maxeval, ctol=ctol)
    if pb.trajectory is not None and pb.reached_task == 0:
        raise ValueError(
            "trajectory: outside the workspace of every design tried "
            f"({loc.nevals + (0 if x0 is not None else prescan)} designs within "
            f"the bounds of {list(pb.names)}): widen the bounds or the joint "
            "limits, or move the task")
    ds = pb.design(loc.x)
    obj, con = pb.values(loc.x)
    feasible = all(v <= ctol for v in con.values())
    result = Optimum(design=ds, objective=objective, value=obj[objective],
                     variables={k: float(v) for k, v in zip(
                         pb.names, pb.lo + loc.x * (pb.hi - pb.lo))},
                     constraints=con, feasible=feasible,
                     converged=loc.converged, status=loc.status,
                     algorithm=algorithm, nevals=loc.nevals, seed=seed,
                     problem=pb)
    if not loc.converged or not feasible:
        why = [] if loc.converged else [f"NLopt stopped with {loc.status} "
                                        "before meeting its tolerances"]
        if not feasible:
            broken = [k for k, v in con.items() if v > ctol]
            why.append(f"the design breaks {', '.join(broken)}")
        warnings.warn(f"optimise: {'; '.join(why)}", ConvergenceWarning,
                      stacklevel=2)
    return result


def neighbourhood(opt: Optimum, *, half_width: float = 0.05, n: int = 9
                  ) -> tuple[float, Design | None, int]:
    """The best feasible design of a dense grid around an optimum: n nodes
    per variable over +- half_width of its bound's span (clipped to the
    bounds).  Returns (its objective value, the design, the number of
    feasible nodes); (NaN, None, 0) when none is feasible.  An optimum is
    a local one when no node beats it."""
    pb = opt.problem
    x = np.array([(opt.variables[k] - pb.lo[j]) / (pb.hi[j] - pb.lo[j])
                  for j, k in enumerate(pb.names)])
    axes = [np.clip(np.linspace(v - half_width, v + half_width, n), 0, 1) for v in x]
    sense = OBJECTIVES[opt.objective][0]
    best: tuple[float, Design | None] = (math.inf, None)
    count = 0
    for node in np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, len(x)):
        obj, con = pb.values(node)
        if all(v <= 0 for v in con.values()) and np.isfinite(obj[opt.objective]):
            count += 1
            if sense * obj[opt.objective] < best[0]:
                best = (sense * obj[opt.objective], pb.design(node))
    return (sense * best[0] if best[1] is not None else math.nan), best[1], count


@dataclass(frozen=True)
class Pareto:
    """The feasible non-dominated designs NSGA-II found."""

    designs: list[Design]            #: the designs, in order of the first objective
    variables: FloatArray            #: (k, nvar) their design variables
    variable_names: tuple[str, ...]  #: the variables' names
    objectives: FloatArray           #: (k, nobj) objectives, natural units and sense
    objective_names: tuple[str, ...] #: the objectives' names
    constraints: FloatArray          #: (k, ncon) constraint values, <= 0 met
    constraint_names: tuple[str, ...]  #: their names
    seed: int                        #: the seed of the run
    pop_size: int                    #: population size
    n_gen: int                       #: generations
    nevals: int                      #: designs evaluated

    def hypervolume(self, reference: Mapping[str, float]) -> float:
        """The objective space the front dominates up to the reference
        point (one value per objective, in its unit: e.g. ``{"peak_force":
        20.0, "volume": 0.0}``), the product of the objectives' units."""
        if set(reference) != set(self.objective_names):
            raise ValueError(f"reference: expected values of "
                             f"{list(self.objective_names)}, got {sorted(reference)}")
        sense = np.array([OBJECTIVES[k][0] for k in self.objective_names])
        ref = sense * np.array([real_number(reference[k], f"reference[{k!r}]")
                                for k in self.objective_names])
        return _optimise.hypervolume(sense * self.objectives, ref)


def pareto(variables: Mapping[str, Sequence[float]],
           objectives: Sequence[str] = ("peak_force", "volume"), *,
           base: Design | None = None,
           trajectory: Trajectory | Spec | None = None,
           samples: int | None = None, grid: Grid | None = None,
           covers: ArrayLike | None = None, volume_min: float | None = None,
           force_max: float | None = None, lti_min: float | None = None,
           pop_size: int = 40, n_gen: int = 40, seed: int = 1,
           platform_mass: str = "fixed", options: Options | None = None) -> Pareto:
    """The Pareto front of two or more objectives under constraints, by
    pymoo's NSGA-II.

    Args: as ``optimise`` (objectives: two or more of OBJECTIVES), and
        pop_size, n_gen: population and generations of NSGA-II;
        seed: its random seed (recorded in the result: the same seed gives
        the same front).

    Returns:
        Pareto: the feasible non-dominated designs (none when no design
        met the constraints).

    Raises:
        ValueError: as ``optimise``.
    """
    if isinstance(objectives, str) or len(objectives) < 2:
        raise ValueError(f"objectives: expected two or more of "
                         f"{', '.join(OBJECTIVES)}, got {objectives!r}")
    for name, v, least in (("pop_size", pop_size, 2), ("n_gen", n_gen, 1),
                           ("seed", seed, 0)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < least:
            raise ValueError(f"{name}: expected an integer >= {least}, got {v!r}")
    pb = _problem(variables, tuple(objectives), base, trajectory, samples, grid,
                  covers, volume_min, force_max, lti_min, options, platform_mass)
    ncon = len(pb.constraint_names)

    def fun(X: FloatArray) -> tuple[FloatArray, FloatArray]:
        rows = [pb.minimised(x) for x in X]
        return (np.array([r[0] for r in rows]),
                np.array([r[1] for r in rows]).reshape(len(X), ncon))

    fr = _optimise.nsga2(fun, len(pb.names), len(objectives), ncon,
                         pop_size=pop_size, n_gen=n_gen, seed=seed)
    if pb.trajectory is not None and pb.reached_task == 0:
        raise ValueError(
            f"trajectory: outside the workspace of every design tried ({fr.nevals} "
            f"designs within the bounds of {list(pb.names)}): widen the bounds or "
            "the joint limits, or move the task")
    order = np.argsort(fr.f[:, 0], kind="stable")
    X = fr.x[order]
    sense = np.array([OBJECTIVES[k][0] for k in objectives])
    return Pareto(designs=[pb.design(x) for x in X],
                  variables=pb.lo + X * (pb.hi - pb.lo), variable_names=pb.names,
                  objectives=fr.f[order] * sense, objective_names=tuple(objectives),
                  constraints=fr.g[order], constraint_names=pb.constraint_names,
                  seed=int(seed), pop_size=int(pop_size), n_gen=int(n_gen),
                  nevals=fr.nevals)

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
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from rps3._core import FloatArray, buf, text
from rps3._rps3 import ffi, lib
from rps3.errors import error, points3, real_number
from rps3.model import Model

if TYPE_CHECKING:  # xarray is imported by evaluate alone
    import xarray as xr

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
        if lib.rps3_design_model(self._c(), ffi.new("rps3_model *"),
                                 chk) != lib.RPS3_OK:
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
        chk = ffi.new("rps3_check *")
        if lib.rps3_design_model(self._c(), m, chk) != lib.RPS3_OK:
            raise ValueError(text(chk.msg))
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


# ------------------------------------------------------------ optimisation

#: the optimisers' names, defined in rps3.design_opt and read from here
_OPTIMISATION = ("ConvergenceWarning", "OBJECTIVES", "DERIVED", "Optimum", "optimise",
                 "neighbourhood", "Pareto", "pareto")


#: a task's requirements, defined in rps3.design_task
_TASK = ("Task", "task")


def __getattr__(name: str) -> Any:
    # the optimisers on first use: rps3.design_opt imports this module
    if name in _OPTIMISATION:
        from rps3 import design_opt
        return getattr(design_opt, name)
    if name in _TASK:
        from rps3 import design_task
        return getattr(design_task, name)
    raise AttributeError(f"module 'rps3.design' has no attribute {name!r}")

"""General layouts' identification end to end (docs/identification.md,
"Data in, parameters out"): a random physically consistent general model's
forces from the library's inverse dynamics written as a data table, read,
fitted (base parameters, then the consistent fit of every layout
parameter), written as HDF5 and as a scene's manipulator section that the
runner plays; the command line with --layout; a small Monte Carlo."""

import numpy as np
import pytest
import rps3
from conftest import write_scene

pytest.importorskip("scipy")
import h5py  # noqa: E402
from rps3 import ident, ident_cli, ident_excite, ident_io, ident_paper, ident_sim  # noqa: E402
from test_cf import offline  # noqa: E402, F401

#: noise-free base estimates against K @ truth: each one's error times its
#: column's RMS, over the RMS force.  Least squares on exact data leaves
#: rounding times the column-scaled condition number (~5e3 here): measured
#: ~1e-13
TOL_BASE = 1e-9
#: the consistent fit's held-out forces against the truth model's, over the
#: largest force, at the default regularisation (reg 1e-9 times the total
#: pseudo-inertia trace: on exact data it pulls the parameters the motion
#: excites least, measured 2e-4 for legs each, 5e-5 identical) ...
TOL_REG_PULL = 1e-3
#: ... and with reg 0: the fit reproduces the truth's base parameters,
#: the rest of the optimisation's tolerance (measured ~3e-13)
TOL_NO_REG = 1e-8
#: the runner's forces of the written section against the fitted model's:
#: one formulation at the same states, the table's nodes played exactly
#: (measured ~1e-15)
TOL_RUNNER = 1e-9
#: how far manipulator_yaml's bodies move the standard parameters to make
#: them acceptable to the library, relative to the body's scale, for a fit
#: that is consistent: rounding (measured ~5e-18)
TOL_MOVED = 1e-12

#: base estimates from differentiated, filtered states of exact data:
#: the zero-phase filter's distortion of the regressor's nonlinear
#: columns, each error's force over the RMS force (measured 2e-3)
TOL_FILTER = 1e-2

GEO = ident_paper.Geometry(vreg=0.01)
DT = 0.005                      # 200 Hz
SPAN = 10.0                     # s: two periods of the 0.2 Hz series
Q0, AMP = (0.0, 0.25, 0.31), (1.5, 0.12, 0.03)


def random_body(rng, kind):
    """A box of random mass (0.05-0.3 kg), sides (1-10 cm), orientation and
    centre of mass: a cylinder's ahead of its pin along the link, a
    piston's behind its ball joint."""
    mass = rng.uniform(0.05, 0.3)
    a, b, c = rng.uniform(0.01, 0.10, 3)
    Ib = mass / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    com = rng.uniform(-0.05, 0.05, 3)
    if kind == "cylinder":
        com[0] = rng.uniform(0.05, 0.15)
    if kind == "piston":
        com[0] = -rng.uniform(0.03, 0.12)
    return rps3.Body(mass, com, Q @ Ib @ Q.T)


def random_law(rng, scale):
    return dict(viscous=rng.uniform(0.2, 1.0) * scale, coulomb=rng.uniform(0.05, 0.3) * scale,
                vreg=GEO.vreg)


def truth_model(seed, legs, friction=("prismatic", "pin")):
    """A Model of random general bodies and friction of the layout: three
    different legs and per-leg friction (legs "each"), or identical legs
    and one law per kind (legs "identical")."""
    rng = np.random.default_rng(seed)
    platform = random_body(rng, "platform")
    if legs == "each":
        bodies = dict(platform=platform, legs=[
            dict(cylinder=random_body(rng, "cylinder"), piston=random_body(rng, "piston"))
            for _ in range(3)])
        prism = [random_law(rng, 2.0) for _ in range(3)]
        pin = [random_law(rng, 0.05) for _ in range(3)]
    else:
        bodies = dict(platform=platform, cylinder=random_body(rng, "cylinder"),
                      piston=random_body(rng, "piston"))
        prism, pin = random_law(rng, 2.0), random_law(rng, 0.05)
    return rps3.Model(bodies=bodies, prismatic_friction=prism if "prismatic" in friction
                      else None, friction=pin if "pin" in friction else None,
                      effects=[*rps3.DEFAULT_EFFECTS, *(f"{k}_friction" for k in friction)])


def forces_along(model, fo, t):
    q, dq, ddq = fo.eval(t)
    return q, dq, ddq, model.inverse(q, dq, ddq).force


@pytest.fixture(scope="module", params=["each", "identical"])
def case(request, tmp_path_factory):
    """(layout, truth model, its layout parameters, data path, fit)."""
    legs = request.param
    lay = ident.Layout(legs=legs)
    model = truth_model(11 if legs == "each" else 12, legs)
    fo = ident_excite.random_fourier(Q0, AMP, 0.2, 6, seed=3)
    t = np.arange(int(round(SPAN / DT)) + 1) * DT
    q, dq, ddq, F = forces_along(model, fo, t)
    mot = rps3.velocity.pose_rates(model, q, dq, ddq)
    path = tmp_path_factory.mktemp(legs) / "measured.h5"
    ident_io.save_data(str(path), t, mot.l, F, dl=mot.dl, ddl=mot.ddl)
    std = ident.std_params(model)
    truth = np.linalg.lstsq(lay.matrix, std, rcond=None)[0]
    # the truth is of the layout (identical legs: the three legs' alike)
    assert np.abs(lay.matrix @ truth - std).max() <= 1e-14 * np.abs(std).max()
    res = ident_io.fit(ident_io.load(path), geometry=GEO, layout=lay)
    return lay, model, truth, path, res


def held_out(model, seed=9):
    """Another motion: a different series, 100 Hz over 8 s."""
    fo = ident_excite.random_fourier(Q0, (1.2, 0.1, 0.025), 0.25, 5, seed=seed)
    t = np.arange(801) * 0.01
    q, dq, ddq, F = forces_along(model, fo, t)
    mot = rps3.velocity.pose_rates(model, q, dq, ddq)
    return ident_io.Data("held-out", t, mot.l, mot.dl, mot.ddl, None, "",
                         {"rates": "measured", "accelerations": "measured"}), F


def test_round_trip_noise_free(case):
    """save_data, load, fit(layout=): the base estimates are K @ truth to
    rounding; the consistent fit is consistent, and its forces on another
    motion are the truth's to the regulariser's pull."""
    lay, model, truth, _, res = case
    assert res.layout == lay and res.pset is None
    est, base = res.estimate, res.base
    assert est.names == base.base_names
    assert base.rank == {"each": 37, "identical": 19}[lay.legs]
    Yb = res.Y.reshape(-1, base.rank)
    share = (np.abs(est.theta - base.of(truth)) * np.sqrt(np.mean(Yb**2, axis=0))
             / np.sqrt(np.mean(res.F**2)))
    print(f"\n{lay.legs}: cond {est.cond:.3g}, largest base error's force {share.max():.2g}")
    assert share.max() <= TOL_BASE
    assert res.consistent and res.report.ok and res.consistent_fit.consistent
    assert np.array_equal(res.standard, lay.matrix @ res.consistent_fit.pi)
    assert "consistent fit:" in res.consistency
    data, F2 = held_out(model)
    t2, Fp = ident_io.predict(res, data)
    err = np.abs(Fp - F2).max() / np.abs(F2).max()
    _, Fe = ident_io.predict(res, data, which="estimate")
    err_est = np.abs(Fe - F2).max() / np.abs(F2).max()
    print(f"held-out: consistent fit {err:.2g}, base estimate {err_est:.2g} of the largest force")
    assert err <= TOL_REG_PULL and err_est <= TOL_BASE * 100
    # the fitted Model, as manipulator_yaml writes it, predicts the same
    Fm = ident_io.fitted_model(res).inverse(*ident_io.states(data, GEO)[1:4]).force
    assert np.abs(Fm - Fp).max() <= TOL_RUNNER * np.abs(F2).max()


def test_consistent_fit_without_regularisation():
    """reg 0: the consistent fit's held-out forces are the truth's."""
    model = truth_model(13, "each", friction=("prismatic",))
    lay = ident.Layout(legs="each", friction=("prismatic",))
    fo = ident_excite.random_fourier(Q0, AMP, 0.2, 6, seed=4)
    t = np.arange(2001) * DT
    q, dq, ddq, F = forces_along(model, fo, t)
    mot = rps3.velocity.pose_rates(model, q, dq, ddq)
    d = ident_io.Data("sim", t, mot.l, mot.dl, mot.ddl, F, "",
                      {"rates": "measured", "accelerations": "measured"})
    res = ident_io.fit(d, geometry=GEO, layout=lay, method="wls", reg=0.0)
    assert res.consistent and res.consistent_fit.converged
    data, F2 = held_out(model, seed=5)
    err = np.abs(ident_io.predict(res, data)[1] - F2).max() / np.abs(F2).max()
    print(f"\nheld-out with reg 0: {err:.2g} of the largest force")
    assert err <= TOL_NO_REG


def test_fit_arguments_refused(case):
    _, _, _, path, _ = case
    d = ident_io.load(path)
    with pytest.raises(ValueError, match="not both"):
        ident_io.fit(d, layout=ident.Layout(), pset=ident_paper.PaperSet())
    with pytest.raises(ValueError, match="method"):
        ident_io.fit(d, layout=ident.Layout(), method="iv")


def test_not_exciting_names_the_combinations(tmp_path):
    """At rest only gravity acts: NotExcitingError names the parameters and
    the condition number, for a general layout as for the paper's."""
    t = 0.01 * np.arange(300)
    l = np.tile(rps3.Model().ik([0.3, 0.2, 0.3]).l, (300, 1))
    d = ident_io.Data("rest", t, l, 0 * l, 0 * l, np.ones((300, 3)), "",
                      {"rates": "measured", "accelerations": "measured"})
    with pytest.raises(ident.NotExcitingError, match="condition number") as exc:
        ident_io.fit(d, layout=ident.Layout(legs="identical"))
    bad = exc.value.unidentifiable
    assert bad and all(n in str(exc.value) for n in bad)
    assert set(bad) <= set(ident.Layout(legs="identical").names)


# ------------------------------------------------------------ the scene

def test_scene_section_plays_in_the_runner(runner, case, tmp_path):
    """manipulator_yaml's section with a table trajectory appended runs in
    rps3-run; its forces are those of the fitted standard parameters
    through the library's regressor (independent of the section's
    centre-of-mass form) and of fitted_model's inverse dynamics."""
    pytest.importorskip("yaml")
    import yaml

    lay, _, _, _, res = case
    text = ident_io.manipulator_yaml(res)
    sec = yaml.safe_load(text)["manipulator"]
    assert sec["bodies"] == "general" and sec["R"] == GEO.R
    if lay.legs == "each":
        assert {"leg1", "leg2", "leg3"} <= set(sec) and "cylinder" in sec["leg2"]
    else:
        assert {"cylinder", "piston", "prismatic_friction", "pin_friction"} <= set(sec["legs"])
    fo = ident_excite.random_fourier(Q0, (1.0, 0.1, 0.02), 0.25, 4, seed=8)
    table = tmp_path / "motion.h5"
    ident_excite.write_table(str(table), fo, dt=0.02)
    n = int(round(fo.period / 0.02)) + 1
    scene = write_scene(tmp_path / "s.yaml", text + f"""\
trajectory:
  kind: table
  table: {{file: {table.name}}}
  samples: {n}
""")
    ds = rps3.scene.run(scene, runner=runner)
    F = np.squeeze(ds.force.values)
    t = np.squeeze(ds.time.values)
    q, dq, ddq = fo.eval(t)
    eff = [*rps3.DEFAULT_EFFECTS, "prismatic_friction", "pin_friction"]
    # the regressor of any model of the geometry, effects and vreg (its
    # bodies do not enter): the section's forces from the standard
    # parameters alone
    ref = rps3.Model(friction=dict(vreg=GEO.vreg), prismatic_friction=dict(vreg=GEO.vreg),
                     effects=eff)
    Fstd = ident.regressor_std(ref, q, dq, ddq) @ res.standard
    Fmodel = ident_io.fitted_model(res).inverse(q, dq, ddq).force
    scale = np.abs(Fstd).max()
    print(f"\nrunner against the standard parameters: {np.abs(F - Fstd).max() / scale:.2g}")
    assert np.abs(F - Fstd).max() <= TOL_RUNNER * scale
    assert np.abs(Fmodel - Fstd).max() <= TOL_RUNNER * scale
    assert max(b.moved for b in ident_io.scene_bodies(res).values()) <= TOL_MOVED


def boundary_bodies(rng, n):
    """Standard parameters on the pseudo-inertia cone's boundary, as a
    consistent fit leaves them: point masses and rods off the origin, a
    massless body with inertia, a negative eigenvalue of 1e-11 of the
    body's scale (within the fit's tolerance), a mass a rounding above 0."""
    for k in range(n):
        m, c = rng.uniform(0.05, 0.3), rng.uniform(-0.2, 0.2, 3)
        u = rng.normal(size=3)
        u /= np.linalg.norm(u)
        Sig = m * rng.uniform(0.01, 0.2) ** 2 / 12 * np.outer(u, u)
        Ic = np.trace(Sig) * np.eye(3) - Sig if k % 2 else np.zeros((3, 3))
        yield ident.body_parameters(m, c, Ic)
    p = ident.body_parameters(0.0, inertia=[1e-4, 2e-4, 2.5e-4])
    yield p
    q = ident.body_parameters(0.1, [0.05, 0.01, 0.0], [0.0, 1e-4, 1e-4])
    scale = np.abs(np.linalg.eigvalsh(ident.pseudo_inertia(q))).max()
    q[4] -= 2e-11 * scale         # Sigma_o[1,1] + Sigma_o[2,2] - ...: Ixx down
    yield q
    yield np.array([1e-20, 1e-21, 0, 0, 1e-5, 0, 0, 1e-5, 0, 2e-5])


def test_boundary_bodies_are_written_acceptably():
    """scene_body makes every consistent body one the library accepts (the
    runner's check, rps3_model_init), moving its standard parameters by
    rounding; the naive conversion (Body.from_parameters) is refused for
    some of the same bodies (this test's reason to exist)."""
    rng = np.random.default_rng(1)
    refused = 0
    for p in boundary_bodies(rng, 200):
        scale = np.abs(np.linalg.eigvalsh(ident.pseudo_inertia(p))).max()
        try:
            rps3.Model(bodies=dict(platform=rps3.Body.from_parameters(p)))
        except ValueError:
            refused += 1
        sb = ident_io.scene_body(p)
        body = rps3.Body(sb.mass, sb.com, sb.inertia)
        m = rps3.Model(bodies=dict(platform=body))
        back = ident.std_params(m)[:10]
        moved = np.abs(back - p).max() / scale
        assert moved <= 3e-11 and abs(sb.moved - moved) <= 1e-15, (p, moved)
        if p[0] <= ident_io.MASS_REL * scale:
            assert sb.mass == 0 and np.all(sb.com == 0)
    assert refused >= 5
    # a massless body with inertia: com 0 and its inertia about the origin
    sb = ident_io.scene_body(ident.body_parameters(0.0, inertia=[1e-4, 2e-4, 2.5e-4]))
    assert sb.mass == 0 and np.allclose(sb.inertia, [1e-4, 0, 0, 2e-4, 0, 2.5e-4], rtol=1e-15)


def test_inconsistent_fit_writes_no_section(case, tmp_path):
    """A fit without a consistent fit (asked not to, or failed) gives a
    YAML comment, not a section."""
    _, _, _, path, _ = case
    res = ident_io.fit(ident_io.load(path), geometry=GEO, layout=ident.Layout(legs="identical",
                       friction=("prismatic",)), consistent=False)
    text = ident_io.manipulator_yaml(res)
    assert text.startswith("# the fit has no physically consistent bodies to write")
    assert "manipulator:" not in text
    out = tmp_path / "p.h5"
    ident_io.write_results(str(out), res, ident_io.load(path))
    with h5py.File(out, "r") as f:
        assert "base_matrix" in f and "consistent_theta" not in f
        assert int(f.attrs["consistent"]) == 0


def test_unconverged_fit_section_says_so(case):
    """A consistent fit that stopped short of its optimality test (here
    the converged fit marked so) still writes its consistent bodies, with a
    warning comment carrying the library's message; the YAML is the same
    otherwise."""
    import dataclasses

    import yaml

    res = case[4]
    assert res.consistent_fit.converged
    short = dataclasses.replace(res, consistent_fit=dataclasses.replace(
        res.consistent_fit, converged=False, message="no optimality after\n2000 iterations"))
    text, base = ident_io.manipulator_yaml(short), ident_io.manipulator_yaml(res)
    warn = [ln for ln in text.splitlines() if ln.startswith("# warning:")]
    assert warn == ["# warning: the consistent fit stopped short of its optimality test "
                    "(consistent, maybe not optimal): no optimality after 2000 iterations"]
    assert "# warning:" not in base
    assert yaml.safe_load(text) == yaml.safe_load(base)


# ------------------------------------------------------------ the files

MIXED = ("various: see parameter_units", "various: products of parameter_units",
         "various: see layout_parameter_units", "various: see standard_parameter_units",
         "various: parameter_units / layout_parameter_units")


@pytest.mark.usefixtures("offline")
def test_results_file_units_and_cf(case, tmp_path):
    """write_results of a general fit: every dataset has units; the
    parameters' names and units; the grouping, the layout and the
    consistent fit as the Fit holds them; rps3.open_dataset reads it; the
    CF checker finds no error but the mixed units of the parameter
    variables (as for rps3-run's identification files)."""
    lay, _, _, path, res = case
    out = tmp_path / "p.nc"
    ident_io.write_results(str(out), res, ident_io.load(path))
    assert not (tmp_path / "p.nc.part").exists()
    no_units = []
    with h5py.File(out, "r") as f:
        assert f.attrs["Conventions"] == "CF-1.10" and f.attrs["content"] == "identification"
        assert f.attrs["layout_legs"] == lay.legs and int(f.attrs["consistent"]) == 1
        f.visititems(lambda n, o: no_units.append(n) if isinstance(o, h5py.Dataset)
                     and "units" not in o.attrs else None)
        names = [n.decode() for n in f["parameter"][()]]
        assert names == list(res.estimate.names)
        units = [u.decode() for u in f["parameter_units"][()]]
        std_units = dict(zip(ident.STANDARD_NAMES, ident.C_STD_UNITS))
        for n, u in zip(names, units):
            # a base parameter's units are its layout parameter's, those of
            # the standard parameter it stands for (leg 1's when shared)
            head, par = n.split(".")
            key = n if n in std_units else (
                f"{head}1.{par}" if head in ident.FRICTION_KINDS or head in ("cylinder",
                                                                             "piston")
                else n)
            assert u == std_units[key], n
            assert f["parameters"][n].attrs["units"] == u
        np.testing.assert_array_equal(f["base_matrix"][()], res.base.K)
        assert f["base_matrix"].dims[1][0].name == "/layout_parameter"
        np.testing.assert_array_equal(f["layout_matrix"][()], lay.matrix)
        np.testing.assert_array_equal(f["consistent_theta"][()], res.consistent_fit.pi)
        np.testing.assert_array_equal(f["consistent_standard"][()], res.standard)
        assert f["consistent_eigenvalues"].shape == (len(lay.bodies), 4)
        assert [b.decode() for b in f["body"][()]] == list(lay.bodies)
        assert int(f["consistent"][()]) == 1
        assert f["consistent_status"].attrs["message"]
        rel = [r.decode() for r in f["relation"][()]]
        assert rel[0].startswith("platform.m = platform.m + ")
        assert f["time"].attrs["standard_name"] == "time"
    assert no_units == []
    with rps3.open_dataset(out) as ds:
        assert ds.theta.dims == ("parameter",)
        assert ds.consistent_theta.dims == ("layout_parameter",)
        assert ds.base_matrix.dims == ("parameter", "layout_parameter")
        np.testing.assert_array_equal(ds.theta.values, res.estimate.theta)
    from test_cf import ALLOWED_EXCEPTIONS, compliance
    errors, warnings, exceptions = compliance(out, tmp_path)
    assert [e for e in errors if not any(u in e for u in MIXED)] == [], errors
    assert warnings == [], warnings
    assert all(any(a in e for a in ALLOWED_EXCEPTIONS) for e in exceptions), exceptions


# ------------------------------------------------------ the command line

def test_cli_layout(case, tmp_path, capsys):
    """--layout: exit 0, the base parameters printed with their units, the
    file and the YAML section written; the layout's options checked."""
    lay, _, _, path, res = case
    if lay.legs != "identical":
        pytest.skip("one layout is enough for the command line")
    out, yml = tmp_path / "p.h5", tmp_path / "m.yaml"
    argv = ["fit", str(path), "-o", str(out), "--layout", "identical", "--vreg", "0.01",
            "--yaml", str(yml)]
    assert ident_cli.main(argv) == 0
    printed = capsys.readouterr().out
    assert "cylinder.mcx" in printed and "kg m" in printed and "consistent fit:" in printed
    with h5py.File(out, "r") as f:
        np.testing.assert_allclose(f["theta"][()], res.estimate.theta, rtol=0, atol=0)
    assert yml.read_text() == ident_io.manipulator_yaml(res)
    # one friction kind, per leg: 21 base parameters
    assert ident_cli.main(["fit", str(path), "-o", str(out), "--layout", "identical",
                           "--friction", "prismatic", "--friction-per-leg", "yes",
                           "--vreg", "0.01"]) == 0
    with h5py.File(out, "r") as f:
        assert len(f["theta"]) == 21 and int(f.attrs["layout_friction_per_leg"]) == 1


@pytest.mark.parametrize("extra, words", [
    (["--layout", "some"], "invalid choice"),
    (["--layout", "each", "--payload"], "--payload: the paper model's option"),
    (["--layout", "each", "--M", "0.2"], "--M: the paper model's option"),
    (["--layout", "each", "--friction", "sliding"], "--friction: friction: unknown kind"),
    (["--layout", "each", "--friction", ","], "--friction: expected kinds"),
    (["--layout", "each", "--friction", "pin,pin"], "--friction: a kind given twice"),
    (["--friction", "pin"], "--friction: a general layout's option"),
    (["--friction-per-leg", "no"], "--friction-per-leg: a general layout's option"),
    (["--vreg-prismatic", "0.01"], "--vreg-prismatic: a general layout's option"),
])
def test_cli_layout_bad_arguments(case, tmp_path, capsys, extra, words):
    """Bad or mixed options: exit 2, the option named, nothing written."""
    _, _, _, path, _ = case
    out = tmp_path / "p.h5"
    assert ident_cli.main(["fit", str(path), "-o", str(out), *extra]) == 2
    assert words in capsys.readouterr().err
    assert not out.exists()


def test_cli_layout_not_exciting(tmp_path, capsys):
    """A platform at rest: exit 1, 'do not excite', nothing written."""
    rest, out = tmp_path / "rest.csv", tmp_path / "p.h5"
    t = 0.01 * np.arange(200)
    l = np.tile(rps3.Model().ik([0.3, 0.2, 0.3]).l, (200, 1))
    ident_io.save_data(str(rest), t, l, np.ones((200, 3)), dl=0 * l, ddl=0 * l)
    assert ident_cli.main(["fit", str(rest), "-o", str(out), "--layout", "each"]) == 1
    err = capsys.readouterr().err
    assert "do not excite" in err and "condition number" in err
    assert not out.exists() and not (tmp_path / "p.h5.part").exists()


# ------------------------------------------------------------ Monte Carlo

#: a correct 95 % interval covers k of 30 draws, k ~ Binomial(30, 0.95):
#: P(k <= 22) = 8.5e-5, so over the counted parameters (at most 19) a
#: coverage below 23/30 in any has a chance below 2e-3
COVER_MIN_EACH = 23 / 30


def test_monte_carlo_general_small():
    """30 draws of 1 % force noise on a general model (identical legs,
    both friction kinds, 100 Hz over 10 s): the counted parameters'
    coverage in the binomial band, median errors small, bias within the
    noise."""
    model = truth_model(14, "identical")
    lay = ident.Layout(legs="identical")
    fo = ident_excite.random_fourier(Q0, AMP, 0.2, 6, seed=3)
    s = ident_sim.simulate_general(model, fo, lay, periods=2.0, dt=0.01, geometry=GEO)
    st = ident_sim.monte_carlo(s, runs=30, seed=2)
    print("\n" + st.summary())
    c = st.counted
    assert c.sum() >= 5
    assert np.all(st.coverage[c] >= COVER_MIN_EACH)
    assert 0.9 <= np.mean(st.coverage[c]) <= 1.0
    assert np.median(st.median_rel_error[c]) < 0.02
    with pytest.raises(ValueError, match="not of the layout"):
        ident_sim.simulate_general(truth_model(15, "each"), fo, lay, geometry=GEO)
    with pytest.raises(ValueError, match="geometry"):
        ident_sim.simulate_general(model, fo, lay, geometry=ident_paper.Geometry(vreg=0.02))


def test_differentiated_states(case):
    """A table of lengths and forces alone: the rates and accelerations
    differentiated, the forces and the layout's regressor filtered alike;
    the filtered covariance; the base estimates near the truth (the
    filter's distortion of the nonlinear regressor, no noise)."""
    lay, _, truth, path, _ = case
    if lay.legs != "identical":
        pytest.skip("the filtering is the paper path's: one layout is enough")
    d = ident_io.load(path)
    d = ident_io.Data(d.path, d.t, d.l, None, None, d.F, d.sha256,
                      {"rates": "none", "accelerations": "none"})
    res = ident_io.fit(d, geometry=GEO, layout=lay, method="wls")
    assert "differentiated" in res.source["rates"] and "forces" in res.source
    assert res.estimate.cov_kind == "filtered"
    Yb = res.Y.reshape(-1, res.base.rank)
    share = (np.abs(res.estimate.theta - res.base.of(truth))
             * np.sqrt(np.mean(Yb**2, axis=0)) / np.sqrt(np.mean(res.F**2)))
    print(f"\ndifferentiated: largest base error's force {share.max():.2g} of the RMS force")
    assert share.max() <= TOL_FILTER
    assert res.consistent


@pytest.mark.parametrize("lay", [ident.Layout(legs="each", friction_per_leg=False),
                                 ident.Layout(legs="identical", friction_per_leg=True),
                                 ident.Layout(legs="identical", friction=("pin",))],
                         ids=["each-shared-friction", "identical-per-leg", "identical-pin"])
def test_scene_section_of_every_form(runner, case, tmp_path, lay):
    """The section's other forms (friction shared under legs: with legs
    each, per leg under leg1..3 with identical legs, one friction kind),
    fitted to the legs-each data: the runner plays each as its standard
    parameters (the fits need not be good, only written right)."""
    legs, _, _, path, _ = case
    if legs.legs != "each":
        pytest.skip("one data set is enough")
    res = ident_io.fit(ident_io.load(path), geometry=GEO, layout=lay)
    assert res.consistent
    fo = ident_excite.random_fourier(Q0, (1.0, 0.1, 0.02), 0.25, 4, seed=8)
    ident_excite.write_table(str(tmp_path / "motion.h5"), fo, dt=0.02)
    n = int(round(fo.period / 0.02)) + 1
    scene = write_scene(tmp_path / "s.yaml", ident_io.manipulator_yaml(res) + f"""\
trajectory: {{kind: table, table: {{file: motion.h5}}, samples: {n}}}
""")
    ds = rps3.scene.run(scene, runner=runner)
    F, t = np.squeeze(ds.force.values), np.squeeze(ds.time.values)
    ref = rps3.Model(friction=dict(vreg=GEO.vreg), prismatic_friction=dict(vreg=GEO.vreg),
                     effects=[*rps3.DEFAULT_EFFECTS, *(f"{k}_friction" for k in lay.friction)])
    Fstd = ident.regressor_std(ref, *fo.eval(t)) @ res.standard
    assert np.abs(F - Fstd).max() <= TOL_RUNNER * np.abs(Fstd).max()


def test_paper_fit_file_opens_too(case, tmp_path):
    """The paper model's fit writes the same kind of file (content
    "identification", cov over parameter x parameter_column): rps3.
    open_dataset reads it over its parameters."""
    legs, _, _, path, _ = case
    if legs.legs != "identical":
        pytest.skip("one data set is enough")
    d = ident_io.load(path)
    res = ident_io.fit(d, geometry=GEO)
    out = tmp_path / "paper.h5"
    ident_io.write_results(str(out), res, d)
    with rps3.open_dataset(out) as ds:
        assert ds.theta.dims == ("parameter",)
        assert ds.cov.dims == ("parameter", "parameter_column")
        assert list(ds.parameter.values) == ["M", "md", "Ipin", "pin.fv", "pin.fc"]
        assert "base_matrix" not in ds


#: the held-out NRMSE of an unbiased prediction over the force noise level
#: s: sqrt((1 + q) / (1 + s^2)), q the prediction's own error share, about
#: p / N (19 base parameters, 3003 rows: 0.6 %, so sqrt(1 + q) - 1 is
#: 0.3 %), and the noise's sample RMS over the N_h = 2403 held-out rows
#: varies by 1 / sqrt(2 N_h) = 1.4 %: four of those and q bound every draw
NRMSE_BAND_GENERAL = 0.06
#: the requirement: the consistent fit's held-out NRMSE within 2 % of WLS's
RATIO_MAX = 1.02


def test_monte_carlo_consistent_held_out_general():
    """15 draws of 1 % force noise on a general model (identical legs,
    both friction kinds, 100 Hz over 10 s) with the consistent fit of all
    the layout's parameters and a held-out motion (held_out's series)
    with its own noise: every draw's consistent fit is physically
    consistent, its held-out NRMSE within 2 % of WLS's, WLS's at the
    noise level; a held-out motion of another layout is refused."""
    model = truth_model(14, "identical")
    lay = ident.Layout(legs="identical")
    fo = ident_excite.random_fourier(Q0, AMP, 0.2, 6, seed=3)
    s = ident_sim.simulate_general(model, fo, lay, periods=2.0, dt=0.01, geometry=GEO)
    fh = ident_excite.random_fourier(Q0, (1.2, 0.1, 0.025), 0.25, 5, seed=9)
    h = ident_sim.simulate_general(model, fh, lay, periods=2.0, dt=0.01, geometry=GEO)
    assert 3 * len(h.t) == 2403
    st = ident_sim.monte_carlo(s, runs=15, seed=4, consistent=True, holdout=h)
    print("\n" + st.summary())
    assert len(st.consistent) == len(st.nrmse_consistent) == 15 and len(st.maps) == 0
    assert st.consistent.all()
    assert np.all(np.abs(st.nrmse_wls / 0.01 - 1) < NRMSE_BAND_GENERAL)
    assert np.all(np.isfinite(st.ratio)) and st.ratio.max() <= RATIO_MAX
    # without the consistent fit the draws are the same (the held-out
    # noise has its own stream) and only WLS is scored
    st2 = ident_sim.monte_carlo(s, runs=3, seed=4, holdout=h)
    assert np.array_equal(st2.nrmse_wls, st.nrmse_wls[:3])
    assert len(st2.consistent) == len(st2.nrmse_consistent) == 0
    with pytest.raises(ValueError, match="layout"):
        other = ident.Layout(legs="identical", friction=("prismatic",))
        model2 = truth_model(14, "identical", friction=("prismatic",))
        h2 = ident_sim.simulate_general(model2, fh, other, periods=1.0, dt=0.01, geometry=GEO)
        ident_sim.monte_carlo(s, runs=1, holdout=h2)

"""The library's base parameters (rps3_ident_base, rps3.ident.base_c)
against the Python package's own (rps3.ident.base_parameters) on the
library's regressor of the general model: the same columns kept and the
same grouping, for the layouts of docs/identification.md."""

import numpy as np
import pytest
import rps3
from rps3 import ident

# the grouping coefficients from two least-squares solutions of the same
# well-conditioned system (cond of the kept columns ~1e3): 1e-8 is far
# below a wrong grouping (O(1)) and far above rounding
TOL_K = 1e-8


def states(n=300, seed=11):
    rng = np.random.default_rng(seed)
    pose = np.column_stack([rng.uniform(-3, 3, n), rng.uniform(0.12, 0.35, n),
                            rng.uniform(0.22, 0.35, n)])
    dpose = rng.normal(size=(n, 3)) * [1.0, 0.3, 0.05]
    ddpose = rng.normal(size=(n, 3)) * [3.0, 1.0, 0.2]
    return pose, dpose, ddpose


@pytest.mark.parametrize("R,rho", [(0.2286, 0.5), (0.31, 0.37), (0.17, 0.71)])
@pytest.mark.parametrize("layout,count", [
    (ident.Layout(legs="each", friction=()), 25),
    (ident.Layout(legs="each", friction=("prismatic",)), 31),
    (ident.Layout(legs="each", friction=("prismatic", "pin")), 37),
    (ident.Layout(legs="identical", friction=("prismatic",)), 17)])
def test_library_base_is_the_packages(R, rho, layout, count):
    m = rps3.Model(R=R, rho=rho, bodies={"platform": rps3.Body(0.2, (0, 0, 0),
                                                                (1e-3, 1e-3, 2e-3))},
                   effects=[e for e in rps3.EFFECTS if e != "payload"],
                   prismatic_friction={"viscous": 0.0, "coulomb": 0.0, "vreg": 1e-3},
                   friction={"viscous": 0.0, "coulomb": 0.0, "vreg": 0.01})
    Y = layout.regressor(ident.regressor_std(m, *states()))
    py = ident.base_parameters(Y, layout.names)
    c = ident.base_c(Y, layout.names)
    assert c.rank == py.rank == count
    assert list(c.independent) == list(py.independent)
    assert np.max(np.abs(c.K - py.K)) <= TOL_K
    assert c.unidentifiable == py.unidentifiable


def test_base_c_refuses_bad_data():
    Y = np.ones((10, 3))
    Y[4, 2] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        ident.base_c(Y, ("a", "b", "c"))
    with pytest.raises(ident.NotExcitingError):
        ident.base_c(np.zeros((10, 3)), ("a", "b", "c"))

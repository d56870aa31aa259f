"""The size of a runner file: chunks sized to the cases and samples
written, so that a file is within 10 % of the raw size of its data
(uncompressed), and `--check` estimates it before the run."""

import importlib.util
import os
import re

import h5py
import numpy as np
import pytest
from conftest import ROOT, run, write_scene

spec = importlib.util.spec_from_file_location(
    "runner_bench", os.path.join(ROOT, "tests", "bench", "runner_bench.py"))
runner_bench = importlib.util.module_from_spec(spec)
spec.loader.exec_module(runner_bench)

HELIX = """\
manipulator: {R: 0.2286, rho: 0.5, M: 0.18, m_over_M: 0.5, d: 0.1524}
trajectory: {kind: helix, radius: 0.000266, pitch: 0.03048, z0: 0.3048,
             period: 10.0, blend: 1.0, TIME}
sweep:
  SWEEP
"""

SCENES = {
    # 205 cases of 80 samples: tiles of up to 204 cases stored 408 rows
    "edge_tile": ("samples: 80",
                  "manipulator.m_over_M: {from: 0, to: 1, num: 205}"),
    # cases just over a tile (16384 samples): windows of 16384 and 116
    # stored two whole windows
    "windows": ("samples: 16500",
                "manipulator.m_over_M: [0, 0.5, 1]"),
    # a sweep of the span with dt: 1001 to 11001 samples a case; no case
    # may store the longest one's samples
    "spans": ("dt: 0.002",
              "trajectory.period: {from: 2, to: 22, step: 1}"),
}
UNITS = {"B": 1, "kB": 1e3, "MB": 1e6, "GB": 1e9, "TB": 1e12}


def estimate(stdout):
    m = re.search(r"output about ([0-9.]+) (\w+) uncompressed", stdout)
    return float(m.group(1)) * UNITS[m.group(2)]


@pytest.mark.parametrize("name", list(SCENES))
def test_file_is_within_10_percent_of_its_data(runner, tmp_path, name):
    time, sweep = SCENES[name]
    scene = write_scene(tmp_path / f"{name}.yaml",
                        HELIX.replace("TIME", time).replace("SWEEP", sweep))
    check = run(scene, None, "--check")
    assert check.returncode == 0, check.stderr
    out = tmp_path / f"{name}.h5"
    proc = run(scene, out, "-q")
    assert proc.returncode == 0, proc.stderr
    size = os.path.getsize(out)
    samples, raw = runner_bench.raw_bytes(out)
    assert size < 1.10 * raw, (name, size / raw)
    # the estimate counts the chunks the run allocates
    assert abs(estimate(check.stdout) - size) < 0.05 * size, \
        (check.stdout, size)
    with h5py.File(out, "r") as f:
        force = f["force"]
        # no chunk is mostly beyond the data
        assert force.chunks[0] <= force.shape[0]
        assert force.chunks[1] <= force.shape[1]
        if name == "spans":
            # past a case's end: never written, reads as NaN
            nt = (~np.isnan(f["case_time"][()])).sum(axis=1)
            assert nt[0] == 1001 and nt[-1] == 11001
            assert np.isnan(force[0, 1001:]).all()
            assert not np.isnan(force[0, :1001]).any()
            assert (f["solve_niter"][0, 1001:] == -1).all()
            assert not np.isnan(force[-1]).any()

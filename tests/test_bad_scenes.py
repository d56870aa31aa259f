"""Every scene in tests/bad_scenes/ is refused: exit 2, one line
FILE:LINE:COLUMN: key.path: what, and no output file, not even a temporary
one.  The first line of each scene says what is expected:
    # expect: LINE:COLUMN key.path: words of the message
"""

import os
import re

import pytest

from conftest import BAD_SCENES, run

SCENES = sorted(f for f in os.listdir(BAD_SCENES) if f.endswith(".yaml"))


def expectation(path):
    with open(path) as f:
        m = re.match(r"# expect: (\d+:\d+) (\S+): (.*)$", f.readline())
    assert m, f"{path}: first line must be '# expect: L:C key: what'"
    return m.groups()


def test_there_are_bad_scenes():
    assert len(SCENES) >= 30


@pytest.mark.parametrize("name", SCENES)
def test_bad_scene_is_refused(runner, tmp_path, name):
    scene = os.path.join(BAD_SCENES, name)
    loc, key, words = expectation(scene)
    out = tmp_path / "out.h5"
    proc = run(scene, out)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"{scene}:{loc}: {key}: "), lines[0]
    assert words in lines[0], lines[0]
    assert proc.stdout == ""
    assert list(tmp_path.iterdir()) == []


def test_bad_scene_check_mode(runner):
    """--check refuses the same way."""
    scene = os.path.join(BAD_SCENES, "sweep_invalid_case.yaml")
    proc = run(scene, None, "--check")
    assert proc.returncode == 2
    assert ":17:31: manipulator.rho: case 2:" in proc.stderr


def test_unreadable_scene(runner, tmp_path):
    proc = run(tmp_path / "nope.yaml", tmp_path / "o.h5")
    assert proc.returncode == 2
    assert "nope.yaml: (file): cannot open: No such file" in proc.stderr
    assert not (tmp_path / "o.h5").exists()

"""same.py REF OUT [--virtual | --copy]: OUT has every dataset of REF,
bit for bit (tests/test_scale.py's comparison); --virtual: its per-case
datasets are virtual (a join), --copy: none is (self-contained)."""

import os
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                ".."))
from test_scale import assert_same_content  # noqa: E402


def main():
    ref, out = sys.argv[1:3]
    assert_same_content(ref, out)
    with h5py.File(out, "r") as f:
        virtual = f["force"].is_virtual and f["status"].is_virtual
    if "--virtual" in sys.argv[3:] and not virtual:
        sys.exit(f"{out}: not virtual datasets")
    if "--copy" in sys.argv[3:] and virtual:
        sys.exit(f"{out}: virtual datasets, not a self-contained file")


if __name__ == "__main__":
    main()

"""Build hooks of the package; everything else is in pyproject.toml.

- the cffi extension rps3._rps3 (rps3/_build.py: where the library comes
  from, and the checks of what the build needs);
- build_ext always compiles (the route can change between builds);
- the sdist carries the library's C sources and header (the repository's
  src/ and include/, outside this directory) as csrc/, so that a wheel
  builds from the sdist alone on any machine with a C compiler and GSL.
"""

import os
import shutil
import sys

try:
    import cffi  # noqa: F401
except ImportError:
    # without cffi, setuptools would drop the cffi_modules keyword with a
    # warning and build a package without its extension
    sys.exit("rps3: cannot build the extension: cffi is missing from the build "
             "environment: pip install cffi (or build without "
             "--no-build-isolation, which installs it)")

from setuptools import setup
from setuptools.command.build_ext import build_ext
from setuptools.command.sdist import sdist

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)            # the repository
VENDORED = os.path.join(HERE, "csrc")   # in an sdist: the copy


def sources():
    """Where src/ and include/ are, as rps3/_build.py looks for them."""
    for base in (VENDORED, ROOT):
        if (os.path.isfile(os.path.join(base, "include", "rps3.h"))
                and os.path.isdir(os.path.join(base, "src"))):
            return base
    return None


class SdistWithSources(sdist):
    """sdist, plus the library's sources and header in csrc/."""

    def make_release_tree(self, base_dir: str, files: list[str]) -> None:
        super().make_release_tree(base_dir, files)
        base = sources()
        if base is None:
            raise SystemExit(f"rps3: the library's sources are in neither "
                             f"{ROOT} nor {VENDORED}")
        out = os.path.join(base_dir, "csrc")
        for sub, ends in (("src", (".c", ".h")), ("include", (".h",))):
            os.makedirs(os.path.join(out, sub), exist_ok=True)
            for name in sorted(os.listdir(os.path.join(base, sub))):
                if name.endswith(ends):
                    shutil.copy2(os.path.join(base, sub, name),
                                 os.path.join(out, sub, name))
        license_file = os.path.join(base, "LICENSE")
        if os.path.isfile(license_file):
            shutil.copy2(license_file, os.path.join(out, "LICENSE"))


class BuildExtAlways(build_ext):
    """build_ext that always compiles: what the extension links (the
    archive, an installed library or the sources) is decided by
    rps3/_build.py at each build, which setuptools' timestamps do not see,
    so that a build directory kept from another route would be reused."""

    def finalize_options(self) -> None:
        super().finalize_options()
        self.force = True


setup(cffi_modules=["rps3/_build.py:ffibuilder"],
      cmdclass={"sdist": SdistWithSources, "build_ext": BuildExtAlways})

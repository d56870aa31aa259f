"""Build hook for the cffi extension rps3._rps3 (see rps3/_build.py);
everything else is in pyproject.toml."""

from setuptools import setup

setup(cffi_modules=["rps3/_build.py:ffibuilder"])

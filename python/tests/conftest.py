"""Shared by the Python tests."""

import os

import pytest


def plumetrace_with_core():
    """The plumetrace package with its C++ module. A missing module fails the tests, unless the
    build left it out (PLUMETRACE_CORE_OPTIONAL=1, set by CMake), where they are skipped."""
    if os.environ.get("PLUMETRACE_CORE_OPTIONAL") == "1":
        pytest.importorskip("plumetrace._core")
    import plumetrace
    import plumetrace._core  # noqa: F401

    return plumetrace

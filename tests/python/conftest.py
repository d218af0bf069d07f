"""pytest set-up for the Python module's tests.

CTest (python/CMakeLists.txt) sets PYTHONPATH to the build tree's package and
HAIRSCATTER_PYTHON_REFERENCE to the C++ reference program. Run by hand, the tests look
in build/python (what scripts/python.sh builds).
"""

import os
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = ROOT / "build" / "python" / "python"

# By hand, the build tree's module comes first (not one an interrupted package run left in
# /usr); under CTest, PYTHONPATH already names the tree it built.
if "HAIRSCATTER_PYTHON_REFERENCE" not in os.environ and BUILD.is_dir():
    sys.path.insert(0, str(BUILD))


@pytest.fixture(scope="session")
def reference_program():
    path = os.environ.get("HAIRSCATTER_PYTHON_REFERENCE") or str(BUILD / "python_reference")
    if not os.access(path, os.X_OK):
        raise FileNotFoundError(f"the C++ reference program {path} is missing: build the target python_reference")
    return path

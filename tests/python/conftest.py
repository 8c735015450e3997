# The Python module's tests (tests/README.md "Python module"): run by
# tools/run_tests.sh as  PYTHONPATH=build/python /usr/bin/python3 -m pytest tests/python
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("WHITTED_BUILD", ROOT / "build"))
EXECUTABLE = BUILD / "whitted"
SCENES = sorted((ROOT / "scenes").glob("*.xml"))


def run_cli(*args):
    """`whitted ARGS`: (exit status, stderr)."""
    p = subprocess.run([str(EXECUTABLE), *map(str, args)], capture_output=True, text=True, timeout=600)
    return p.returncode, p.stderr


@pytest.fixture(scope="session")
def renderer():
    import whitted
    return whitted.Renderer()

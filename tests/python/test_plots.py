"""python/plots.py runs headless and writes every figure as a PNG."""

import os
import pathlib
import subprocess
import sys

import hairscatter

SCRIPT = pathlib.Path(__file__).resolve().parents[2] / "python" / "plots.py"
FIGURES = ("longitudinal", "azimuthal", "sphere", "swatches", "dual")


def run(*args):
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    env.pop("MPLBACKEND", None)  # the script must choose Agg itself
    # The package this test imported, wherever it came from (the build tree or a prefix).
    env["PYTHONPATH"] = str(pathlib.Path(hairscatter.__file__).parents[1])
    return subprocess.run([sys.executable, str(SCRIPT), *args], env=env, capture_output=True, text=True, timeout=120)


def test_every_figure_is_written_headless(tmp_path):
    r = run("--quick", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    for name in FIGURES:
        png = tmp_path / f"{name}.png"
        data = png.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000, name
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(f"{n}.png" for n in FIGURES)


def test_an_unknown_figure_is_refused(tmp_path):
    r = run("--only", "swatches,nope", "--out", str(tmp_path))
    assert r.returncode == 2 and "unknown figure(s) nope" in r.stderr
    assert not any(tmp_path.iterdir())

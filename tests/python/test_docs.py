"""The Python code of docs/python.md and README.md runs as written."""

import contextlib
import io
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "python.md"


def test_the_first_session_runs():
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), re.S)
    assert len(blocks) == 1
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(blocks[0], str(DOC), "exec"), {})
    lines = out.getvalue().splitlines()
    assert lines[0].startswith("(100000, 3)") and lines[2] == "(64, 3)"


def test_the_readme_snippet_runs():
    readme = ROOT / "README.md"
    blocks = re.findall(r"```python\n(.*?)```", readme.read_text(), re.S)
    assert len(blocks) == 1
    scope = {}
    exec(compile(blocks[0], str(readme), "exec"), scope)
    assert scope["f"].shape == (1000, 3) and str(scope["f"].dtype) == "float32"

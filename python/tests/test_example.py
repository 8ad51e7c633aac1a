"""The README's Python example (docs/example_python.py) runs and draws its figure."""

import os
import struct
import subprocess
import sys

from conftest import SRC

EXAMPLE = os.path.join(SRC, "docs", "example_python.py")


def test_readme_example_runs_and_draws_the_figure(tmp_path):
    png = tmp_path / "tip.png"
    r = subprocess.run([sys.executable, EXAMPLE, str(png)], cwd=SRC, capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "FE residual vibration: peak" in r.stdout and "wrote" in r.stdout
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", data[16:24])  # the IHDR chunk
    assert (width, height) == (1000, 400)
    assert len(data) > 20000  # two panels of curves, not an empty canvas


def test_readme_shows_the_example_as_it_is():
    with open(EXAMPLE) as f:
        code = f.read()
    body = code[code.index("import sys"):]
    with open(os.path.join(SRC, "README.md")) as f:
        readme = f.read()
    assert body in readme, "README.md's Python example differs from docs/example_python.py"

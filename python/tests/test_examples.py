"""The example a newcomer copies runs and prints what it promises."""
import subprocess
import sys

from conftest import REPO


def test_distances_example():
    script = REPO / "examples" / "python" / "distances.py"
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert "mean relative error against the exact field" in r.stdout
    assert "point distances:" in r.stdout
    err = float(r.stdout.split("exact field: ")[1].split("%")[0])
    assert err < 0.5

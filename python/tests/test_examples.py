"""The Python examples run as a reader would run them (their own process, Debian's python3)."""
import os
import pathlib
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR, skip_without_data

EXAMPLES = SOURCE_DIR / "examples" / "python"
IRB120_DATA = SOURCE_DIR / ".." / "shared" / "data" / "irb120_faro"


def run_example(name, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)], capture_output=True, text=True,
                          env=env)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def test_compare_estimators_writes_its_plot(tmp_path):
    out = run_example("compare_estimators.py", tmp_path)
    png = tmp_path / "compare_estimators.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rms = {l.split()[0]: float(l.split("held-out RMS")[1].split()[0]) for l in out.splitlines() if "held-out RMS" in l}
    assert list(rms) == ["nominal", "geometric,ratio_regression", "least_squares"]
    # Both calibrated robots predict the held-out poses far better than the nominal one (8.4 mm), and no
    # better than the held-out poses' own noise (10 um per axis: 17 um RMS) allows.
    assert rms["nominal"] > 5
    for method in ("geometric,ratio_regression", "least_squares"):
        assert 0.017 < rms[method] < 0.2, out


def test_calibrate_irb120_reaches_the_landed_figures():
    if not (IRB120_DATA / "processed_joints.txt").exists():
        out = run_example("calibrate_irb120.py", IRB120_DATA)
        assert out.startswith("skipped:")
        skip_without_data(f"no IRB 120 data in {IRB120_DATA}")
    out = run_example("calibrate_irb120.py", IRB120_DATA)
    rms = {l.split()[0] + (l.split()[1] if l.startswith("+") else ""): float(l.split("held-out RMS")[1].split()[0])
           for l in out.splitlines() if "held-out RMS" in l}
    # tests/estimators/joint_errors_real_data_test.cc: 0.525, 0.461 and 0.275 mm with least_squares.
    assert rms["geometry"] < 0.53 and rms["+gravity"] < 0.47 and rms["+approach"] < 0.28, out
    assert "iteration_limit" not in out

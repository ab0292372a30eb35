"""The course's programs, each run as a student runs it (its own process, Debian's python3), with the
figures it prints asserted. ctest runs one test per program (examples/course/CMakeLists.txt)."""
import math
import os
import pathlib
import re
import subprocess
import sys

import pytest

COURSE = pathlib.Path(__file__).resolve().parent


def run(name, tmp_path, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, str(COURSE / f"{name}.py"), str(tmp_path), *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=60)
    assert done.returncode == 0, done.stdout + done.stderr
    if not done.stdout.startswith("skipped:"):
        plot = tmp_path / f"{name}.png"
        assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", f"no plot {plot}"
    return done.stdout


def numbers(pattern, text):
    """Every match of `pattern` in `text`, its groups as floats."""
    return [tuple(float(g) for g in m.groups()) for m in re.finditer(pattern, text)]


def test_01_conventions(tmp_path):
    out = run("01_conventions", tmp_path)
    gaps = dict(re.findall(r"^(\w+)\s+\d+ parameters, max tool gap to mdh over 200 poses (\S+) mm", out, re.M))
    assert sorted(gaps) == ["dh", "hayati", "mdh", "poe"], out
    assert all(float(g) < 1e-9 for g in gaps.values()), out  # the same kinematics, to rounding
    tilts = numbers(r"tilt\s+(\S+) deg: hayati beta_3 = \S+ deg; mdh d_2 =\s+(\S+) mm, a_2 / tan\(beta\) =\s+(\S+) mm, "
                    r"same pose to (\S+) mm", out)
    assert len(tilts) == 6, out
    for beta, d2, expected, gap in tilts:
        # Craig's frame on the common normal of nearly parallel axes: |d_2| = a_2 / tan(beta), a_2 = 431.8 mm.
        assert abs(abs(d2) - 431.8 / math.tan(math.radians(beta))) < 1e-3 * abs(d2), out
        assert gap < 1e-6, out

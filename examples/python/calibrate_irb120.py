"""Calibrating a real arm: the ABB IRB 120 measured by a laser tracker (../shared/data/irb120_faro).

982 poses: the joint angles the controller read back (deg) and the position of a reflector on the flange
(mm) in the tracker's frame. We fit on the even rows and score on the odd rows, which the fit never saw,
with three models of the arm, each adding what the one before leaves out:

  1. geometry: the modified DH parameters, the tracker's base and the reflector's offset;
  2. + gravity: joints 2 and 3 sag under the weight of the links they carry (an angle error that follows
     the torque of gravity about the joint);
  3. + approach: every joint stops a little short or long depending on how fast it was moving into the pose
     (each row remembers the pose measured before it).

    python3 examples/python/calibrate_irb120.py [DATA_DIR]   # default: <project>/../shared/data/irb120_faro

Without the data folder the script says so and exits with status 0.
"""
import pathlib
import sys

import numpy as np

import kincal

default = pathlib.Path(__file__).resolve().parents[2] / ".." / "shared" / "data" / "irb120_faro"
folder = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else default)
if not (folder / "processed_joints.txt").exists():
    print(f"skipped: no IRB 120 data in {folder}")
    sys.exit(0)

# The measurements, converted to SI at the edge: degrees -> radians, millimetres -> metres.
q = np.radians(np.loadtxt(folder / "processed_joints.txt"))
p = np.loadtxt(folder / "processed_SMR_1.txt") * 1e-3
data = kincal.Dataset(q, p)
train = data.select_rows(range(0, len(data), 2))  # each row keeps the pose that led to it
test = data.select_rows(range(1, len(data), 2))

# The nominal IRB 120 (modified DH, Craig) from the data README, with ABB's joint speeds (deg/s), which
# the approach terms need. The reflector's offset is unknown: the tool starts at the flange.
geometry = """name: irb120
convention: mdh
units: {length: mm, angle: deg}
joints:
  - {alpha: 0, a: 0, theta: 0, d: 290}
  - {alpha: -90, a: 0, theta: -90, d: 0}
  - {alpha: 0, a: 270, theta: 0, d: 0}
  - {alpha: -90, a: 70, theta: 0, d: 302}
  - {alpha: 90, a: 0, theta: 0, d: 0}
  - {alpha: -90, a: 0, theta: 180, d: 72}
limits: [[-165, 165], [-110, 110], [-110, 70], [-160, 160], [-120, 120], [-400, 400]]
velocity_limits: [250, 250, 250, 320, 320, 420]
"""
gravity = "joint_errors:\n  - {joint: 2, type: gravity}\n  - {joint: 3, type: gravity}\n"
approach = "".join(f"  - {{joint: {j}, type: approach}}\n" for j in range(1, 7))
models = {
    "geometry": geometry,
    "+ gravity 2, 3": geometry + gravity,
    "+ approach 1-6": geometry + gravity + approach,
}

nominal = kincal.parse_robot(geometry, "irb120")
print(f"{len(train)} rows to fit, {len(test)} held out; nominal robot: "
      f"{kincal.evaluate(nominal, test)['position_stats']['rms'] * 1e3:.3f} mm RMS")
for label, text in models.items():
    start = kincal.parse_robot(text, "irb120")
    identified, report = kincal.identify(start, train, "least_squares", {"max_iterations": 200})
    rms = kincal.evaluate(identified, test, nominal=start)["position_stats"]["rms"]
    print(f"{label:16s} {report['status']:10s} held-out RMS {rms * 1e3:.3f} mm")

# The last model's approach coefficients: how far each joint overshoots per unit of speed (rad per rad/s).
for parameter in report["parameters"]:
    if parameter["name"].startswith("approach"):
        print(f"  {parameter['name']}: {parameter['value'] * 1e3:.2f} ms ({parameter['value'] * 1e3:.2f} mrad per rad/s)")

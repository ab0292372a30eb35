"""8. A real arm: the ABB IRB 120 measured by a laser tracker (../shared/data/irb120_faro).

982 poses: joint angles read back from the controller and a reflector's position in the tracker's frame.
We fit on the even rows and score on the odd rows, with three models, each adding what the one before
leaves out: the geometry (MDH, tracker base, reflector offset); + gravity (joints 2 and 3 sag under the
links they carry); + approach (each joint stops a little short or long depending on how fast it moved into
the pose). A real arm is not its geometry: the last two terms cut the held-out error almost in half.

    python3 08_real_arm.py [OUT_DIR] [DATA_DIR]       # writes OUT_DIR/08_real_arm.png
Without the data folder the program says "skipped:" and why, and exits with status 0.
"""
from course_env import kincal  # first: one clear line if numpy, matplotlib or kincal is missing
import pathlib, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

out_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
default = pathlib.Path(__file__).resolve().parents[3] / "shared" / "data" / "irb120_faro"
folder = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else default)
if not (folder / "processed_joints.txt").exists():
    print(f"skipped: no IRB 120 data in {folder} (the project's shared data folder, see its README)")
    sys.exit(0)

# The measurements, converted to SI at the edge: degrees -> radians, millimetres -> metres.
data = kincal.Dataset(np.radians(np.loadtxt(folder / "processed_joints.txt")),
                      np.loadtxt(folder / "processed_SMR_1.txt") * 1e-3)
train = data.select_rows(range(0, len(data), 2))  # each row keeps the pose that led to it (for approach)
test = data.select_rows(range(1, len(data), 2))

# The nominal IRB 120 in modified DH (the data's README), with ABB's joint speeds (deg/s) for the approach term.
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
models = {"geometry": geometry, "+ gravity": geometry + gravity, "+ approach": geometry + gravity + approach}

print(f"{len(train)} rows to fit, {len(test)} held out")
errors_mm, fit_rms = {}, {}
for label, text in models.items():
    start = kincal.parse_robot(text, "irb120")
    identified, report = kincal.identify(start, train, "least_squares", {"max_iterations": 200})
    held_out = kincal.evaluate(identified, test, nominal=start)
    errors_mm[label] = held_out["position"] * 1e3
    fit_rms[label] = report["final_rms_m"] * 1e3
    print(f"{label:12s} {report['status']:10s} {report['details']['free_parameters']:3d} parameters, fit RMS "
          f"{fit_rms[label]:.3f} mm, held-out RMS {held_out['position_stats']['rms'] * 1e3:.3f} mm, "
          f"max {held_out['position_stats']['max'] * 1e3:.3f} mm")

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
for label, e in errors_mm.items():
    left.plot(np.sort(e), np.arange(1, len(e) + 1) / len(e), label=label)
left.set(xlabel="held-out position error (mm)", ylabel="fraction of the held-out poses", title="IRB 120, 491 poses")
left.legend()
x = np.arange(len(models))
right.bar(x - 0.2, list(fit_rms.values()), 0.4, label="fitted rows")
right.bar(x + 0.2, [np.sqrt(np.mean(e**2)) for e in errors_mm.values()], 0.4, label="held-out rows")
right.set(xticks=x, xticklabels=list(models), ylabel="RMS position error (mm)", title="Each term earns its place")
right.legend()
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "08_real_arm.png", dpi=100)
print(f"wrote {out_dir / '08_real_arm.png'}")

"""Two estimators, one simulated arm: which one predicts poses it has not seen?

We simulate the seed's six-joint arm. `seed_identified.yaml` plays the real arm (the "truth") and
`seed_nominal.yaml` is what the controller believes. A laser tracker measures the marker with 10 um of
noise while the arm follows the seed's protocol: one joint swept at a time, 20 stops 5 degrees apart. We
identify the arm twice from the same measurements:

  * geometric,ratio_regression: the seed's method. It fits each joint's axis as a circle and then the
    gear ratios (METHOD.md, sections 2 and 3).
  * least_squares: every parameter at once, by Levenberg-Marquardt on the position residuals.

Then we ask each identified robot where the marker will be at 200 random poses it never saw, and plot the
errors. Even a perfect model would show about 17 um there: the tracker's own noise in the held-out poses.

    python3 examples/python/compare_estimators.py OUT_DIR     # writes OUT_DIR/compare_estimators.png
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # write files, no window
import matplotlib.pyplot as plt
import numpy as np

import kincal

robots = pathlib.Path(__file__).resolve().parents[1] / "robots"
out_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")

nominal = kincal.load_robot(robots / "seed_nominal.yaml")
truth = kincal.load_robot(robots / "seed_identified.yaml")

# Everything in SI: noise in metres, angles in radians. The same seed gives the same measurements every run.
train = kincal.simulate(nominal, truth, protocol="sweep", stops=20, step=np.radians(5), noise=10e-6, seed=1)
test = kincal.simulate(nominal, truth, protocol="random", poses=200, noise=10e-6, seed=2)
print(f"{len(train)} training rows (sweeps), {len(test)} held-out rows (random poses)")

# Held-out error of each robot, in mm. The nominal robot is the starting point of both estimators.
errors_mm = {"nominal": kincal.evaluate(nominal, test)["position"] * 1e3}
print(f"{'nominal':28s} {'':10s} held-out RMS {np.sqrt(np.mean(errors_mm['nominal']**2)):.4f} mm")
for method in ["geometric,ratio_regression", "least_squares"]:
    identified, report = kincal.identify(nominal, train, method)
    # The controller (nominal) turned the commanded angles into motor counts: it gives them their meaning.
    errors = kincal.evaluate(identified, test, nominal=nominal)
    errors_mm[method] = errors["position"] * 1e3
    print(f"{method:28s} {report['status']:10s} held-out RMS {errors['position_stats']['rms'] * 1e3:.4f} mm")

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
left.bar(list(errors_mm), [np.sqrt(np.mean(e**2)) for e in errors_mm.values()], color=["grey", "C0", "C1"])
left.set_yscale("log")
left.set_ylabel("held-out RMS position error (mm)")
left.set_title("Before and after calibration")
left.tick_params(axis="x", labelrotation=10)
for method in ["geometric,ratio_regression", "least_squares"]:
    right.hist(errors_mm[method], bins=30, alpha=0.6, label=method)
right.set_xlabel("position error at a held-out pose (mm)")
right.set_ylabel("poses")
right.set_title("The two calibrated robots")
right.legend()
fig.tight_layout()

out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "compare_estimators.png", dpi=100)
print(f"wrote {out_dir / 'compare_estimators.png'}")

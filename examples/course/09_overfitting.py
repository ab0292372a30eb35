"""9. Overfitting and model selection: a richer model can predict worse.

The "real" arm here is the seed's identified arm plus a small eccentricity in joints 2 and 3 (a once-per-turn
angle error of 0.004 deg in sin and in cos). Two models are fitted to the same measurements (30 um noise): the
geometry (MDH and ratios, 33 free parameters) and the geometry with sin/cos terms of orders 1 and 2 on every
joint (up to 24 more). On few poses the richer model fits the noise and predicts held-out poses worse; on many it
captures the eccentricity and wins. Cross-validation (5 folds of the training rows, no held-out data
needed) sees the same thing from the training set alone and picks the better model for each size (its
errors include the scored rows' own noise, 30 um x sqrt(3) = 52 um: only the comparison counts). The
estimators' `select: true` does the same among nested models, adding the terms joint by joint.

    python3 09_overfitting.py [OUT_DIR]               # writes OUT_DIR/09_overfitting.png
"""
from course_env import kincal  # first: one clear line if numpy, matplotlib or kincal is missing
import pathlib, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

robots = pathlib.Path(__file__).resolve().parents[1] / "robots"
out_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
seed_text = (robots / "seed_identified.yaml").read_text()
truth = kincal.parse_robot(seed_text + "joint_errors:\n" + "".join(
    f"  - {{joint: {j}, type: harmonic, orders: [1], coefficients: {{sin1: 0.004, cos1: 0.004}}}}\n" for j in (2, 3)))
nominal_text = (robots / "seed_nominal.yaml").read_text()
models = {"geometry": kincal.parse_robot(nominal_text),
          "+ harmonics": kincal.parse_robot(nominal_text + "joint_errors:\n" + "".join(
              f"  - {{joint: {j}, type: harmonic, orders: [1, 2]}}\n" for j in range(1, 7)))}
nominal = models["geometry"]
test = kincal.simulate(nominal, truth, protocol="random", poses=300, noise=0.0, seed=99)


def fit_and_score(start, train, scored):
    identified, report = kincal.identify(start, train, "least_squares", {"max_iterations": 100})
    return kincal.evaluate(identified, scored, nominal=start)["position_stats"]["rms"], report


def cross_validation(start, train, folds=5):
    """RMS of each fold's rows predicted by the model fitted to the other folds."""
    rows = np.arange(len(train))
    errors = [fit_and_score(start, train.select_rows(rows[rows % folds != k]),
                            train.select_rows(rows[rows % folds == k]))[0] for k in range(folds)]
    return np.sqrt(np.mean(np.square(errors)))


sizes = [25, 40, 60, 100, 200, 400]
held_out = {label: [] for label in models}
for n in sizes:
    train = kincal.simulate(nominal, truth, protocol="random", poses=n, noise=30e-6, seed=n)
    line = f"{n:3d} poses:"
    for label, start in models.items():
        rms, report = fit_and_score(start, train, test)
        held_out[label].append(rms)
        line += f" {label} {report['details']['free_parameters']:2d} free, held-out {rms * 1e3:.4f} mm;"
    print(line)
for n in (40, 400):
    train = kincal.simulate(nominal, truth, protocol="random", poses=n, noise=30e-6, seed=n)
    cv = {label: cross_validation(start, train) for label, start in models.items()}
    best = min(cv, key=cv.get)
    truth_best = min(models, key=lambda label: held_out[label][sizes.index(n)])
    print(f"{n:3d} poses, 5-fold cross-validation: " + ", ".join(f"{k} {v * 1e3:.4f} mm" for k, v in cv.items())
          + f" -> chooses {best}; held-out best: {truth_best}")
    # `select: true` does it inside the estimator, among nested models: geometry, + harmonic 1, + harmonic 2, ...
    _, report = kincal.identify(models["+ harmonics"], train, "least_squares", {"select": True})
    table = report["details"]["selection"]["candidates"]
    chosen = next(c for c in table if c["chosen"])
    print(f"{n:3d} poses, select: true chooses {chosen['candidate']} ({chosen['parameters']} parameters) "
          f"among {len(table)} nested models")

fig, ax = plt.subplots(figsize=(6, 4))
for label, rms in held_out.items():
    ax.loglog(sizes, np.array(rms) * 1e3, "o-", label=label)
ax.set(xlabel="training poses", ylabel="held-out RMS position error (mm)", title="More parameters need more data")
ax.legend()
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "09_overfitting.png", dpi=100)
print(f"wrote {out_dir / '09_overfitting.png'}")

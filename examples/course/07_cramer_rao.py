"""7. Noise and the Cramer-Rao bound: are the reported standard deviations true?

Every estimate comes with a standard deviation per parameter: sigma^2 (J^T J)^-1 at the solution, with sigma
estimated from the residuals. For least squares with Gaussian noise that is the Cramer-Rao bound, the
smallest spread any unbiased estimator can reach, and Gauss-Newton reaches it. We check it the experimental
way: the same 40 poses measured 200 times with fresh 20 um noise, identified each time, and the spread of
each parameter over the runs compared with what one run reports.

    python3 07_cramer_rao.py [OUT_DIR]                # writes OUT_DIR/07_cramer_rao.png
"""
from course_env import kincal  # first: one clear line if numpy, matplotlib or kincal is missing
import pathlib, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

robots = pathlib.Path(__file__).resolve().parents[1] / "robots"
out_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
nominal = kincal.load_robot(robots / "seed_nominal.yaml")
truth = kincal.load_robot(robots / "seed_identified.yaml")
sigma, runs = 20e-6, 200

exact = kincal.simulate(nominal, truth, protocol="random", poses=40, noise=0.0, seed=1).to_numpy()
rng = np.random.default_rng(7)
values, reported, sigmas = [], [], []
for run in range(runs):
    data = kincal.Dataset(exact["q"], exact["p"] + rng.normal(0, sigma, exact["p"].shape))
    _, report = kincal.identify(nominal, data, "least_squares")
    free = [p for p in report["parameters"] if p["free"]]
    values.append([p["value"] for p in free])
    reported.append([p["stddev"] for p in free])
    sigmas.append(report["details"]["sigma_m"])
    if run == 0:
        names, units = [p["name"] for p in free], [p["unit"] for p in free]
        print(f"{len(free)} free parameters, {report['num_measurements']} poses x 3 coordinates")
values, reported = np.array(values), np.array(reported)
print(f"sigma from the residuals, mean over the runs {np.mean(sigmas) * 1e6:.2f} um (true {sigma * 1e6:.0f} um)")
monte_carlo = values.std(axis=0, ddof=1)
ratio = monte_carlo / reported.mean(axis=0)
for name in ("a_2", "d_3", "alpha_3", "theta_2", "ratio_2", "base_x"):
    i = names.index(name)
    scale = 1e6 if units[i] in ("m", "rad") else 1.0
    unit = {"m": "um", "rad": "urad"}.get(units[i], "")
    print(f"{name:8s} Monte Carlo {monte_carlo[i] * scale:9.3f} {unit:4s} reported {reported[:, i].mean() * scale:9.3f} "
          f"{unit:4s} ratio {ratio[i]:.3f}")
print(f"all {len(names)} parameters: Monte Carlo / reported, median {np.median(ratio):.3f}, "
      f"range {ratio.min():.3f} to {ratio.max():.3f} (200 runs: +-{1 / np.sqrt(2 * (runs - 1)):.3f} sampling error)")

fig, ax = plt.subplots(figsize=(5, 5))
lengths = np.array([u == "m" for u in units])
for mask, label in [(lengths, "lengths (m)"), (~lengths, "angles (rad), ratios")]:
    ax.loglog(reported.mean(axis=0)[mask], monte_carlo[mask], "o", label=label)
lim = [reported.mean(axis=0).min() / 2, reported.mean(axis=0).max() * 2]
ax.loglog(lim, lim, "k--", label="equal")
ax.set(xlabel="reported standard deviation (one run)", ylabel="spread over 200 runs",
       title="The reported uncertainty is the real one")
ax.legend()
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "07_cramer_rao.png", dpi=100)
print(f"wrote {out_dir / '07_cramer_rao.png'}")

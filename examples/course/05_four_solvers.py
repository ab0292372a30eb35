"""5. Four solvers, one minimum.

The same least-squares problem (every identifiable parameter of the seed's arm and its ratios, from 60
random poses measured with 10 um of noise) solved by our own Levenberg-Marquardt (least_squares), Ceres
Solver, NLopt's SLSQP and Ipopt. A well-posed problem has one minimum: all four must find the same
parameters and the same residual; what differs is how many iterations (and evaluations) and how long.

    python3 05_four_solvers.py [OUT_DIR]              # writes OUT_DIR/05_four_solvers.png
"""
from course_env import kincal  # first: one clear line if numpy, matplotlib or kincal is missing
import pathlib, sys, time
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

robots = pathlib.Path(__file__).resolve().parents[1] / "robots"
out_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
nominal = kincal.load_robot(robots / "seed_nominal.yaml")
truth = kincal.load_robot(robots / "seed_identified.yaml")
train = kincal.simulate(nominal, truth, protocol="random", poses=60, noise=10e-6, seed=1)
test = kincal.simulate(nominal, truth, protocol="random", poses=200, noise=0.0, seed=2)

solvers = ["least_squares", "ceres", "nlopt", "ipopt"]
results = {}
for method in solvers:  # every one is built: CMake requires Ceres, NLopt and Ipopt
    times = []
    for _ in range(3):  # the best of three: the first run pays for loading and caches
        start = time.perf_counter()
        identified, report = kincal.identify(nominal, train, method)
        times.append(time.perf_counter() - start)
    values = np.array([p["value"] for p in report["parameters"]])
    held_out = kincal.evaluate(identified, test, nominal=nominal)["position_stats"]["rms"]
    results[method] = (report["iterations"], min(times), report["final_rms_m"], values, held_out)
    print(f"{method:14s} {report['status']:10s} {report['iterations']:4d} iterations {min(times) * 1e3:7.1f} ms, "
          f"residual RMS {report['final_rms_m'] * 1e3:.6f} mm, held-out error {held_out * 1e3:.4f} mm")

reference = results["least_squares"][3]
for method, (_, _, _, values, _) in results.items():
    gap = np.abs(values - reference) / np.maximum(np.abs(reference), 1.0)  # relative for ratios, absolute else
    print(f"{method:14s} largest parameter difference from least_squares {gap.max():.2e} (m, rad, relative ratio)")

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
left.bar(list(results), [r[0] for r in results.values()], color=["C0", "C1", "C2", "C3"][: len(results)])
left.set(yscale="log", ylabel="iterations", title="Same minimum, different paths")
right.bar(list(results), [r[1] * 1e3 for r in results.values()], color=["C0", "C1", "C2", "C3"][: len(results)])
right.set(yscale="log", ylabel="wall time (ms, best of 3)", title="60 poses, 33 parameters + 6 ratios")
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "05_four_solvers.png", dpi=100)
print(f"wrote {out_dir / '05_four_solvers.png'}")

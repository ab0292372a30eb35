"""4. The error model: the parameter Jacobian, redundant parameters, observability indices O1-O5.

Calibration linearises the tool position in the parameters: dp = J dphi, one 3 x 36 block per pose. Some
columns of J are combinations of others at every pose, so no data can separate them: the singular values
of J fall to zero, and the null space names the combinations (the first row of the chain against the base,
the last joint's theta and d against the tool, the tool's orientation against nothing when only its origin
is measured). The indices O1-O5 (Sun & Hollerbach 2008) score how well a pose set observes the rest; they
compare the seed's sweeps (120 poses, one joint at a time) with 120 random poses.

    python3 04_error_model.py [OUT_DIR]               # writes OUT_DIR/04_error_model.png
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
names = nominal.parameter_names
# A typical error of each parameter (1 mm, 1 mrad), as the library scales J for the indices.
scale = np.full(len(names), 1e-3)

pose_sets = {"sweeps": kincal.simulate(nominal, truth, protocol="sweep", noise=10e-6, seed=1),
             "random": kincal.simulate(nominal, truth, protocol="random", poses=120, noise=10e-6, seed=1)}
singular = {}
for label, data in pose_sets.items():
    q = data.to_numpy()["q"]
    J = np.vstack([nominal.parameter_jacobian(qk)[:3] for qk in q])  # position rows, at the tool origin
    Jn = J / np.linalg.norm(J, axis=0).clip(1e-300)                 # unit columns: units do not decide
    _, s, Vt = np.linalg.svd(Jn)
    rank = int((s > 1e-9 * s[0]).sum())
    print(f"{label}: J is {J.shape[0]} x {J.shape[1]}, rank {rank}, {J.shape[1] - rank} combinations unobservable")
    _, report = kincal.identify(nominal, data, "least_squares")
    o = report["details"]["observability"]
    held = [h["name"] for h in report["details"]["held_parameters"]]
    keep = [i for i, n in enumerate(names) if n not in held]
    # J_c: the identifiable columns, plus the ratios (dq_i/dK_i = -q_i/K_i; a typical error is 1e-3 K_i).
    R = np.vstack([-1e-3 * nominal.joint_jacobian(qk)[:3] * qk for qk in q])
    sc = np.linalg.svd(np.hstack([J[:, keep] * scale[keep], R]), compute_uv=False)
    mine = [np.exp(np.log(sc).mean()) / np.sqrt(len(q)), sc[-1] / sc[0], sc[-1], sc[-1] ** 2 / sc[0], 1 / (1 / sc).sum()]
    for h in report["details"]["held_parameters"]:  # each held column against the kept ones
        col = J[:, names.index(h["name"])]
        if label == "random" or not col.any():
            continue
        c, *_ = np.linalg.lstsq(J[:, keep], col, rcond=None)
        sine = np.linalg.norm(J[:, keep] @ c - col) / np.linalg.norm(col)
        top = [f"{c[k]:+.3f} {names[keep[k]]}" for k in np.argsort(-np.abs(c))[:2] if abs(c[k]) > 1e-6]
        print(f"  {h['name']:8s} = {' '.join(top)} residual {sine:.1e}; library: {h['reason']}")
    print(f"{label}: held {len(held)} ({', '.join(held)})")
    print(f"{label}: O1 {o['O1']:.4g} O2 {o['O2']:.4g} O3 {o['O3']:.4g} O4 {o['O4']:.4g} O5 {o['O5']:.4g} (library)")
    print(f"{label}: O1 {mine[0]:.4g} O2 {mine[1]:.4g} O3 {mine[2]:.4g} O4 {mine[3]:.4g} O5 {mine[4]:.4g} (from J here)")
    singular[label] = s

fig, ax = plt.subplots(figsize=(6, 4))
for label, s in singular.items():
    ax.semilogy(np.arange(1, len(s) + 1), np.maximum(s, 1e-17), "o-", label=f"{label} (120 poses)")
ax.set(xlabel="index", ylabel="singular value of the column-normalised J", title="Where the redundancies are")
ax.legend()
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "04_error_model.png", dpi=100)
print(f"wrote {out_dir / '04_error_model.png'}")

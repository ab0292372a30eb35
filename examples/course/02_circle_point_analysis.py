"""2. Circle point analysis, step by step, on a noisy sweep (METHOD.md section 2).

A marker on the seed's arm is measured while one joint turns at a time. Each joint's arc gives its axis:
fit a plane (its normal is the axis direction), fit a circle in that plane (its centre is a point of the
axis). Two neighbouring axes give their common normal, whose length and angle are the MDH row's a and
alpha. The arc's length decides the accuracy: the seed's 20 stops 2 degrees apart (a 38-degree arc)
against 12 stops 10 degrees apart (110 degrees), with a 0.1 mm tracker (the seed's Optotrak), 40 runs each.

    python3 02_circle_point_analysis.py [OUT_DIR]     # writes OUT_DIR/02_circle_point_analysis.png
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
truth = kincal.load_robot(robots / "seed_identified.yaml")  # Table 2 and Table 3 of the seed


def fit_axis(P, q):
    """Plane by SVD, circle in the plane (algebraic, then 5 Gauss-Newton steps on the distances), axis."""
    c = P.mean(axis=0)
    u, v, normal = np.linalg.svd(P - c)[2]
    xy = np.c_[(P - c) @ u, (P - c) @ v]
    centre = np.linalg.lstsq(np.c_[2 * xy, np.ones(len(xy))], (xy**2).sum(axis=1), rcond=None)[0][:2]  # Kasa
    for _ in range(5):  # geometric fit: minimise sum (|x - centre| - r)^2
        diff = xy - centre
        dist = np.linalg.norm(diff, axis=1)
        J = np.c_[-diff / dist[:, None], -np.ones(len(xy))]
        centre = centre + np.linalg.lstsq(J, dist.mean() - dist, rcond=None)[0][:2]
    S = c + centre[0] * u + centre[1] * v
    turn = np.cross(P[0] - S, P[-1] - S) @ normal
    return S, normal * np.sign(turn * (q[-1] - q[0])), np.abs(P @ normal - c @ normal).max()


def sweep_axes(data):
    """Per swept joint: fitted axis and the truth's axis (frame i of the truth arm at the sweep's start)."""
    a = data.to_numpy()
    axes = {}
    for s in np.unique(a["sweep"]):
        rows = np.flatnonzero(a["sweep"] == s)
        joint = int(np.argmax(np.ptp(a["q"][rows], axis=0)))
        S, z, plane = fit_axis(a["p"][rows], a["q"][rows, joint])
        q_actual = truth.actual_angles(a["q"][rows[0]], controller=nominal)
        frame = truth.frame_poses(q_actual)[joint + 1]
        angle = np.degrees(np.arccos(np.clip(z @ frame[:3, 2], -1, 1)))
        offset = np.linalg.norm(np.cross(S - frame[:3, 3], frame[:3, 2]))  # distance of S from the true axis
        axes[joint + 1] = (S, z, angle, offset, plane)
    return axes


for noise in (0.0, 1e-4):  # without noise, the common normal gives the truth's row exactly
    fit = sweep_axes(kincal.simulate(nominal, truth, protocol="sweep", noise=noise, seed=1))
    for j, (S, z, angle, offset, plane) in sorted(fit.items()) if noise else []:
        print(f"joint {j}: plane flatness {plane * 1e3:.3f} mm, axis direction error {angle:.4f} deg, "
              f"axis position error {offset * 1e3:.3f} mm")
    (S2, z2), (S3, z3) = fit[2][:2], fit[3][:2]
    x2 = np.cross(z2, z3) / np.linalg.norm(np.cross(z2, z3))
    print(f"noise {noise * 1e3:.1f} mm, common normal of axes 2 and 3: a_3 = {abs((S3 - S2) @ x2) * 1e3:.4f} mm, "
          f"alpha_3 = {np.degrees(np.arccos(z2 @ z3)):.4f} deg (the seed's Table 2: 1.68 mm, 90.24 deg)")

results = {}
for label, stops, step in [("2 deg x 20", 20, 2.0), ("10 deg x 12", 12, 10.0)]:
    runs = [sweep_axes(kincal.simulate(nominal, truth, protocol="sweep", stops=stops, step=np.radians(step),
                                       noise=1e-4, seed=seed)) for seed in range(1, 41)]
    results[label] = {k: np.sqrt(np.mean([[r[j][k] ** 2 for j in range(1, 7)] for r in runs], axis=0))
                      for k in (2, 3)}
    print(f"{label:12s} RMS over 40 runs, joints 1-6: direction "
          + " ".join(f"{v:.4f}" for v in results[label][2]) + " deg; position "
          + " ".join(f"{v * 1e3:.3f}" for v in results[label][3]) + " mm")

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
for i, (label, r) in enumerate(results.items()):
    for ax, values in ((left, r[2]), (right, r[3] * 1e3)):
        ax.bar(np.arange(1, 7) + 0.4 * i - 0.2, values, 0.4, label=label)
left.set(yscale="log", xlabel="joint", ylabel="axis direction error, RMS (deg)", title="Direction (plane normal)")
right.set(yscale="log", xlabel="joint", ylabel="axis position error, RMS (mm)", title="Position (circle centre)")
left.legend()
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "02_circle_point_analysis.png", dpi=100)
print(f"wrote {out_dir / '02_circle_point_analysis.png'}")

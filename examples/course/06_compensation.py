"""6. Compensation as the seed does it (METHOD.md section 4), beside two others.

Knowing the real arm (here the seed's identified one, Tables 2 and 3) is not enough: the controller still
computes joints with the nominal model. Compensation finds the joints that put the real arm on the target.
The seed's pose-matrix differential stacks the 12 entries of T_target - T(theta) and of dT/dtheta_i and
steps theta by the least-squares solution; the paper reports 1e-12 in about 4 iterations. Newton's method
converges quadratically: the error is squared at every step. Beside it, the 6-D Jacobian method (the same
idea on a twist) and the joint-space compensator (3 fixed steps of a precomputed correction).

    python3 06_compensation.py [OUT_DIR]              # writes OUT_DIR/06_compensation.png
"""
import pathlib, sys, time
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import kincal

robots = pathlib.Path(__file__).resolve().parents[1] / "robots"
out_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
nominal = kincal.load_robot(robots / "seed_nominal.yaml")
truth = kincal.load_robot(robots / "seed_identified.yaml")

# 20 reachable targets, away from the wrist singularity (joint 5 at 0).
rng = np.random.default_rng(3)
q_true = rng.uniform(0.8 * nominal.limits[:, 0], 0.8 * nominal.limits[:, 1], size=(20, 6))
q_true[:, 4] = rng.choice([-1, 1], 20) * np.radians(rng.uniform(20, 90, 20))
targets = np.array([truth.fk(q) for q in q_true])
# The controller's solution theta_m: the nominal arm's inverse kinematics on the same branch. Every method
# starts there, as the paper does.
theta_m = kincal.compensate(nominal, nominal, targets, "jacobian", seeds=q_true)["q_command"]


def on_the_real_arm(q_command):
    """Where the real arm goes for these commands (the controller converts them with the nominal ratios)."""
    poses = [truth.fk(truth.actual_angles(q, controller=nominal)) for q in q_command]
    position = [np.linalg.norm(T[:3, 3] - G[:3, 3]) for T, G in zip(poses, targets)]
    angle = [2 * np.arcsin(np.linalg.norm(T[:3, :3] - G[:3, :3]) / np.sqrt(8)) for T, G in zip(poses, targets)]
    return np.array(position), np.array(angle)


methods = {"none": None, "analytic_derivative": {"plain": True}, "jacobian": {}, "joint_space": {}}
for method, options in methods.items():
    start = time.perf_counter()
    result = kincal.compensate(nominal, truth, targets, method, options, seeds=theta_m)
    per_target = (time.perf_counter() - start) / len(targets)
    position, angle = on_the_real_arm(result["q_command"])
    if method == "none":
        start_error = np.median(position)  # iteration 0: the controller's theta_m on the real arm
    converged = sum(s == "converged" for s in result["status"])
    print(f"{method:20s} converged {converged:2d}/20, iterations median {np.median(result['iterations']):.0f} max "
          f"{result['iterations'].max()}; on the real arm: position median {np.median(position) * 1e3:.2e} max "
          f"{position.max() * 1e3:.2e} mm, "
          f"orientation mean {np.degrees(angle.mean()):.2e} deg; {per_target * 1e3:.2f} ms per target")

# Newton's convergence: stop after k iterations and look at the median error over the targets.
curves = {}
for method, options in [("analytic_derivative", {"plain": True}), ("jacobian", {})]:
    curves[method] = [start_error]
    for k in range(1, 6):
        result = kincal.compensate(nominal, truth, targets, method, dict(options, max_iterations=k), seeds=theta_m)
        curves[method].append(np.median(on_the_real_arm(result["q_command"])[0]))
    print(f"{method:20s} median position error after 1-5 iterations: "
          + " ".join(f"{e * 1e3:.1e}" for e in curves[method][1:]) + " mm")

fig, ax = plt.subplots(figsize=(6, 4))
for (method, curve), style in zip(curves.items(), ["o-", "x--"]):
    ax.semilogy(range(6), np.maximum(np.array(curve) * 1e3, 1e-16), style, label=method)
ax.axhline(1e-12, color="grey", ls="--", label="the paper's 1e-12")
ax.set(xlabel="iterations (0: the nominal solution)", ylabel="median position error on the real arm (mm)",
       title="Quadratic convergence from the nominal solution")
ax.legend()
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "06_compensation.png", dpi=100)
print(f"wrote {out_dir / '06_compensation.png'}")

"""6. Compensation as the seed does it (METHOD.md section 4), beside two others.

Knowing the real arm (here the seed's identified one, Tables 2 and 3) is not enough: the controller still
computes joints with the nominal model. Compensation finds the joints that put the real arm on the target.
The seed's pose-matrix differential stacks the 12 entries of T_target - T(theta) and of dT/dtheta_i and
steps theta by the least-squares solution; the paper reports 1e-12 in about 4 iterations. Newton's method
converges quadratically: the error is squared at every step. Beside it, the 6-D Jacobian method (the same
idea on a twist) and the joint-space compensator (3 fixed steps of a precomputed correction).

The arm has two singular configurations (the 6 x 6 Jacobian loses rank at any other joint angles): joint 4 at 0,
the elbow straight, where axes 3 and 5 are collinear (joints 3 and 5 turned opposite ways leave the tool where
it is), and joint 5 at +-90 degrees. Near them a small pose error takes a large counter-rotation of joints 3
and 5: Newton's iterations still get there, 3 fixed steps from the controller's solution need not.

    python3 06_compensation.py [OUT_DIR]              # writes OUT_DIR/06_compensation.png
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

# 20 reachable targets; joint 5 between 20 and 90 degrees either way, so some lie near its singularity at 90.
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




def conditioning(robot, q):
    """sigma_min / sigma_max of the 6 x 6 Jacobian, position rows in units of 0.5 m (the compensators' scale)."""
    s = np.linalg.svd(np.diag([2, 2, 2, 1, 1, 1]) @ robot.joint_jacobian(q), compute_uv=False)
    return s[-1] / s[0]


methods = {"none": None, "analytic_derivative": {"plain": True}, "jacobian": {}, "joint_space": {}}
results = {}
for method, options in methods.items():
    start = time.perf_counter()
    result = results[method] = kincal.compensate(nominal, truth, targets, method, options, seeds=theta_m)
    per_target = (time.perf_counter() - start) / len(targets)
    position, angle = on_the_real_arm(result["q_command"])
    if method == "none":
        start_error = np.median(position)  # iteration 0: the controller's theta_m on the real arm
    converged = sum(s == "converged" for s in result["status"])
    print(f"{method:20s} converged {converged:2d}/20, iterations median {np.median(result['iterations']):.0f} max "
          f"{result['iterations'].max()}; on the real arm: position median {np.median(position) * 1e3:.2e} max "
          f"{position.max() * 1e3:.2e} mm, "
          f"orientation mean {np.degrees(angle.mean()):.2e} deg; {per_target * 1e3:.2f} ms per target")

# Where joint_space stops short: the real arm's solution (the one the Newton methods reach) and the
# controller's solution it starts from, their joints 4 and 5 and conditioning, and the correction between them.
q_solution = results["jacobian"]["q_actual"]
for i in np.flatnonzero(np.asarray(results["joint_space"]["status"]) != "converged"):
    correction = np.degrees(results["jacobian"]["q_command"][i] - theta_m[i])
    print(f"joint_space target {i:2d}: {results['joint_space']['status'][i]}, "
          f"{results['joint_space']['position_error'][i] * 1e3:.2e} mm off; "
          f"solution q4 {np.degrees(q_solution[i, 3]):.1f} q5 {np.degrees(q_solution[i, 4]):.1f} deg, "
          f"sigma ratio {conditioning(truth, q_solution[i]):.1e}; "
          f"controller's q4 {np.degrees(theta_m[i, 3]):.1f} q5 {np.degrees(theta_m[i, 4]):.1f} deg, "
          f"sigma ratio {conditioning(nominal, theta_m[i]):.1e}; correction of joints 3 and 5 "
          f"{correction[2]:.1f} {correction[4]:.1f} deg")
others = [conditioning(truth, q) for q, s in zip(q_solution, results["joint_space"]["status"]) if s == "converged"]
print(f"sigma ratio at the solutions of the other targets: median {np.median(others):.1e}")

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

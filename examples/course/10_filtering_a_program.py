"""10. Filtering a robot program: the calibration reaches the controller without touching it.

A controller only knows its nominal model; its inverse kinematics turns each Cartesian target of a program
into joints. `kincal filter` rewrites the program instead: every target is replaced by the pose that, given
to the nominal controller, makes the real (identified) arm reach the original target (programs/filter.h;
RoboDK's FilterProgram). Here a UR10 whose real geometry is up to 1 mm and 0.1 deg off its data sheet runs
a URScript square; we check the filtered program the way the arm would run it: the controller's inverse
kinematics (nearest the joints it comes from) of each written pose, then the real arm's forward kinematics.

    python3 10_filtering_a_program.py [OUT_DIR]       # writes OUT_DIR/10_filtering_a_program.png
"""
from course_env import cli as course_env_cli, kincal  # first: one clear line if numpy, matplotlib or kincal is missing
import os, pathlib, re, subprocess, sys, tempfile
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

root = pathlib.Path(__file__).resolve().parents[2]
cli = course_env_cli()
out_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
work = pathlib.Path(tempfile.mkdtemp())
nominal_file = root / "examples" / "robots" / "ur10_dh.yaml"
nominal = kincal.load_robot(nominal_file)
real = nominal.copy()  # the identified arm: every length up to 1 mm and every angle up to 0.1 deg off
rng = np.random.default_rng(10)
size = np.where(np.array(nominal.parameter_units) == "m", 1e-3, np.radians(0.1))
joints = np.array([not n.startswith(("base", "tool")) for n in nominal.parameter_names])  # same base and tool
real.parameters = nominal.parameters + rng.uniform(-1, 1, len(size)) * size * joints
real.save(work / "real.yaml")

# The program: a 200 mm square, tool pointing down, from a joint start; URScript poses are p[x, y, z, rx, ry, rz].
q_start = np.radians([0, -90, 90, -90, -90, 0])
T_start = nominal.fk(q_start)
targets = []
for dx, dy in [(0, 0), (0.2, 0), (0.2, 0.2), (0, 0.2), (0, 0)]:
    targets.append(T_start.copy())
    targets[-1][:3, 3] += [dx - 0.1, dy - 0.1, -0.1]


def rotation_vector(R):  # axis times angle (0 < angle < pi)
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    return angle / (2 * np.sin(angle)) * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])


def rotation_matrix(v):  # Rodrigues
    k = np.cross(np.eye(3), v / np.linalg.norm(v))
    return np.eye(3) + np.sin(np.linalg.norm(v)) * k + (1 - np.cos(np.linalg.norm(v))) * k @ k


lines = ["def square():", "  movej([" + ", ".join(f"{q:.6f}" for q in q_start) + "], a=1.4, v=1.05)"]
for T in targets:
    pose = list(T[:3, 3]) + list(rotation_vector(T[:3, :3]))
    lines.append("  movel(p[" + ", ".join(f"{v:.9f}" for v in pose) + "], a=1.2, v=0.25)")
(work / "square.script").write_text("\n".join(lines + ["end", ""]))
done = subprocess.run([cli, "filter", "--nominal", str(nominal_file), "--identified", str(work / "real.yaml"),
                       "--program", str(work / "square.script"), "--out", str(work / "filtered.script")],
                       capture_output=True, text=True, check=True)
print(done.stdout.strip())
original, written = ([np.array([float(v) for v in m.split(",")])
                      for m in re.findall(r"movel\(p\[([^\]]*)\]", (work / name).read_text())]
                     for name in ("square.script", "filtered.script"))

def run_on_the_real_arm(poses):
    """The controller's inverse kinematics, nearest the joints it comes from, then the real arm."""
    q, errors = q_start, []
    for pose, target in zip(poses, targets):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = rotation_matrix(pose[3:]), pose[:3]
        q = kincal.compensate(nominal, nominal, T[None], "jacobian", seeds=q[None])["q_command"][0]
        errors.append(np.linalg.norm(real.fk(q)[:3, 3] - target[:3, 3]))
    return np.array(errors)


before, after = run_on_the_real_arm(original), run_on_the_real_arm(written)
moved = [np.linalg.norm(w[:3] - o[:3]) for w, o in zip(written, original)]
for k in range(len(targets)):
    print(f"target {k + 1}: written {moved[k] * 1e3:.3f} mm away; real arm off by {before[k] * 1e3:.3f} mm "
          f"unfiltered, {after[k] * 1e3:.2e} mm filtered")

fig, ax = plt.subplots(figsize=(6, 4))
x = np.arange(1, len(targets) + 1)
ax.bar(x - 0.2, before * 1e3, 0.4, label="original program")
ax.bar(x + 0.2, np.maximum(after * 1e3, 1e-9), 0.4, label="filtered program")
ax.set(yscale="log", xlabel="target", ylabel="real arm's position error (mm)", title="A UR10 square, filtered")
ax.legend()
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "10_filtering_a_program.png", dpi=100)
print(f"wrote {out_dir / '10_filtering_a_program.png'}")

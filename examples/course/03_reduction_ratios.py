"""3. Reduction ratios from encoder counts (METHOD.md section 3, the seed's Table 3).

The controller turns a commanded angle into motor counts with the nominal ratio; the joint turns by what
those counts mean with its real ratio. While a joint is swept, the tracker's arc gives the angle it really
turned (about the fitted axis) and the encoder the motor angle: the slope of one against the other is the
ratio. A ratio 0.2 % off (joint 2: 7946.45 nominal, 7964.34 identified) is an angle error that grows with
the angle, 0.2 deg at 90 deg, which no DH parameter can absorb: millimetres at the tool.

    python3 03_reduction_ratios.py [OUT_DIR]          # writes OUT_DIR/03_reduction_ratios.png
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
truth = kincal.load_robot(robots / "seed_identified.yaml")  # the identified ratios of Table 3
table3 = [7947.74, 7964.34, 4815.60, 5157.69, 4022.85, 4170.54]
counts_per_rev = 2048

data = kincal.simulate(nominal, truth, protocol="sweep", noise=10e-6, seed=1)
identified, report = kincal.identify(nominal, data, "geometric,ratio_regression")
axes = {a["joint"]: a for a in report["stages"][0]["details"]["axes"]}
a = data.to_numpy()
fits = {}
for s in np.unique(a["sweep"]):
    rows = np.flatnonzero(a["sweep"] == s)
    j = int(np.argmax(np.ptp(a["q"][rows], axis=0)))
    z, S = np.array(axes[j + 1]["direction"]), np.array(axes[j + 1]["point_m"])
    r = a["p"][rows] - S
    r -= np.outer(r @ z, z)  # the marker's arm about the axis, in the plane of the circle
    theta_a = np.unwrap([np.arctan2(np.cross(r[0], v) @ z, r[0] @ v) for v in r])  # angle turned, from the arc
    theta_e = 2 * np.pi * (a["encoders"][rows, j] - a["encoders"][rows[0], j]) / counts_per_rev  # motor angle
    fits[j] = (theta_a, theta_e, np.polyfit(theta_a, theta_e, 1)[0])
ratio = {p["name"]: p for p in report["parameters"]}
for j in range(6):
    lib = ratio[f"ratio_{j + 1}"]
    print(f"joint {j + 1}: nominal {ratio[f'ratio_{j + 1}']['nominal']:8.2f}, slope of the arc {fits[j][2]:8.2f}, "
          f"ratio_regression {lib['value']:8.2f} +- {lib['stddev']:.2f}, Table 3 {table3[j]:8.2f}")

# A wrong ratio at the tool: command each joint alone from 0 to 90 deg with the nominal ratios on the real arm.
commanded = np.radians(np.linspace(0, 90, 31))
tool_error_mm = np.zeros((6, len(commanded)))
for j in range(6):
    for k, angle in enumerate(commanded):
        q = np.zeros(6)
        q[j] = angle
        q_actual = truth.actual_angles(q, controller=nominal)
        tool_error_mm[j, k] = np.linalg.norm(truth.fk(q_actual)[:3, 3] - truth.fk(q)[:3, 3]) * 1e3
    q_actual = truth.actual_angles(np.radians(np.eye(6)[j] * 90), controller=nominal)
    print(f"joint {j + 1} commanded 90 deg: turns {np.degrees(q_actual[j]):.4f} deg "
          f"(90 x nominal / actual ratio = {90 * ratio[f'ratio_{j + 1}']['nominal'] / table3[j]:.4f}), "
          f"tool {tool_error_mm[j, -1]:.3f} mm away")

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
theta_a, theta_e, slope = fits[1]
k_nominal = ratio["ratio_2"]["nominal"]  # what the motor turned beyond what the nominal ratio says
left.plot(np.degrees(theta_a), (theta_e - k_nominal * theta_a) / (2 * np.pi), "o", label="joint 2's 20 stops")
left.plot(np.degrees(theta_a), (slope - k_nominal) * theta_a / (2 * np.pi), "-", label=f"fit: ratio {slope:.1f}")
left.set(xlabel="joint angle from the arc (deg)", ylabel="motor turns - 7946.45 x joint turns",
         title="Joint 2: the ratio is the slope (Table 3: 7964.34)")
left.legend()
for j in range(6):
    right.plot(np.degrees(commanded), tool_error_mm[j], label=f"joint {j + 1}")
right.set(xlabel="commanded angle (deg)", ylabel="tool position error (mm)", title="Nominal ratios on the real arm")
right.legend()
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "03_reduction_ratios.png", dpi=100)
print(f"wrote {out_dir / '03_reduction_ratios.png'}")

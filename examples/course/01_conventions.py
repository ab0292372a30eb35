"""1. One arm, four conventions: why parallel axes need Hayati's extra angle.

The Puma 560 is written in modified DH (Craig), converted with `kincal convert` to standard DH, Hayati and
product of exponentials (POE), and all four files give the same tool pose at any joint angles (to rounding).
Then joint 3's axis is tilted by a small angle beta, out of parallel with joint 2's: Hayati takes it as
beta = the tilt, while MDH has to move its frame to where the two axes' common normal now is, at
d = a_2 / tan(beta) (431.8 mm / tan(1 deg) = 24.7 m). A calibration in MDH would have to find that number.

    python3 01_conventions.py [OUT_DIR]       # writes OUT_DIR/01_conventions.png; KINCAL_CLI: the program
"""
from course_env import cli as course_env_cli, kincal  # first: one clear line if numpy, matplotlib or kincal is missing
import os, pathlib, subprocess, sys, tempfile
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

root = pathlib.Path(__file__).resolve().parents[2]
cli = course_env_cli()
out_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
work = pathlib.Path(tempfile.mkdtemp())


def convert(path, convention):
    out = work / f"{path.stem}_{convention}.yaml"
    subprocess.run([cli, "convert", str(path), "--to", convention, "--out", str(out)], check=True,
                   stdout=subprocess.DEVNULL)
    return kincal.load_robot(out)


mdh_file = root / "examples" / "robots" / "puma560_mdh.yaml"
puma = {"mdh": kincal.load_robot(mdh_file)}
for convention in ("dh", "hayati", "poe"):
    puma[convention] = convert(mdh_file, convention)

rng = np.random.default_rng(1)
limits = puma["mdh"].limits
qs = rng.uniform(limits[:, 0], limits[:, 1], size=(200, 6))
for convention, robot in puma.items():
    gap = max(np.abs(robot.fk(q) - puma["mdh"].fk(q))[:3, 3].max() for q in qs)
    print(f"{convention:7s} {len(robot.parameter_names):2d} parameters, max tool gap to mdh over 200 poses "
          f"{gap * 1e3:.2e} mm")

# Tilt axis 3 by beta in the Hayati file; convert back to MDH and read where its frames went.
text = (work / "puma560_mdh_hayati.yaml").read_text()
tilts_deg = np.array([0.1, 0.2, 0.5, 1.0, 2.0, 5.0])
d2_mm = []
for beta in tilts_deg:
    tilted = work / f"tilt_{beta}.yaml"
    tilted.write_text(text.replace("a: 431.8, beta: 0,", f"a: 431.8, beta: {beta},"))
    mdh = convert(tilted, "mdh")
    d2_mm.append(mdh.parameter("d_2") * 1e3)
    q = qs[0]
    gap = np.abs(mdh.fk(q) - kincal.load_robot(tilted).fk(q))[:3, 3].max()
    print(f"tilt {beta:4.1f} deg: hayati beta_3 = {beta:.1f} deg; mdh d_2 = {d2_mm[-1]:11.1f} mm, "
          f"a_2 / tan(beta) = {431.8 / np.tan(np.radians(beta)):9.1f} mm, same pose to {gap * 1e3:.1e} mm")

fig, ax = plt.subplots(figsize=(6, 4))
ax.loglog(tilts_deg, np.abs(d2_mm), "o", label="|d_2| of the MDH file")
ax.loglog(tilts_deg, 431.8 / np.tan(np.radians(tilts_deg)), "-", label="431.8 mm / tan(beta)")
ax.loglog(tilts_deg, np.full_like(tilts_deg, 431.8), "--", label="the arm's size (431.8 mm)")
ax.set_xlabel("tilt of axis 3 out of parallel with axis 2 (deg) = Hayati's beta_3")
ax.set_ylabel("MDH offset d_2 (mm)")
ax.set_title("Nearly parallel axes: MDH's frame runs away")
ax.legend()
fig.tight_layout()
out_dir.mkdir(parents=True, exist_ok=True)
fig.savefig(out_dir / "01_conventions.png", dpi=100)
print(f"wrote {out_dir / '01_conventions.png'}")

"""The module and the command line give the same numbers to the last digit: same files in, same library
calls, so every double must be equal (compared with ==, never with a tolerance)."""
import json
import math
import subprocess

import numpy as np
import pytest

import kincal

DEG = math.pi / 180  # the robot files' angle unit, as kincal converts it (value * to_si)
MM = 1e-3


def run(cli, *args):
    done = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def numbers(csv_text):
    """The numeric rows of a CSV file (comment lines and the header left out)."""
    lines = [l for l in csv_text.splitlines() if l and not l.startswith("#")]
    header = lines[0].split(",")
    return header, [l.split(",") for l in lines[1:]]


@pytest.mark.parametrize("robot_file", ["seed_identified.yaml", "irb120_mdh.yaml", "ur10_dh.yaml"])
def test_fk_matches_kincal_fk(cli, robots, robot_file):
    robot = kincal.load_robot(robots / robot_file)
    rng = np.random.default_rng(11)
    for _ in range(5):
        q_deg = np.round(rng.uniform(-90, 90, robot.dof), 3)
        printed = json.loads(run(cli, "fk", robots / robot_file, "--q=" + ",".join(repr(float(v)) for v in q_deg)))
        assert printed["units"]["length"] == robot.length_unit
        to_si = {"mm": MM, "m": 1.0}[robot.length_unit]
        T = robot.fk(q_deg * DEG)
        expected = np.array(printed["T"])
        assert np.array_equal(T[:3, :3], expected[:3, :3])
        assert np.array_equal(T[:3, 3] / to_si, expected[:3, 3])  # kincal fk prints metres / to_si


@pytest.fixture
def simulated(cli, robots, tmp_path):
    """`kincal simulate` of the seed's arm (random poses, 10 um noise), with the module's own simulation."""
    path = tmp_path / "sim.csv"
    run(cli, "simulate", "--nominal", robots / "seed_nominal.yaml", "--truth", robots / "seed_identified.yaml",
        "--protocol", "random", "--poses", 40, "--noise", "10um", "--seed", 5, "--out", path)
    return path


def test_simulate_matches_kincal_simulate(robots, simulated):
    nominal = kincal.load_robot(robots / "seed_nominal.yaml")
    truth = kincal.load_robot(robots / "seed_identified.yaml")
    data = kincal.simulate(nominal, truth, protocol="random", poses=40, noise=10 * 1e-6, seed=5)
    strip = lambda text: [l for l in text.splitlines() if not l.startswith("#")]
    assert strip(data.to_csv()) == strip(simulated.read_text())


@pytest.mark.parametrize("method,options", [("least_squares", None), ("least_squares", {"max_iterations": 3}),
                                            ("ceres", None)])
def test_identify_and_predict_match_the_command_line(cli, robots, simulated, tmp_path, method, options):
    nominal_path = robots / "seed_nominal.yaml"
    args = ["identify", "--nominal", nominal_path, "--data", simulated, "--method", method,
            "--out", tmp_path / "id.yaml", "--report", tmp_path / "report.json"]
    if options:
        (tmp_path / "options.yaml").write_text(json.dumps(options))  # JSON is YAML
        args += ["--options", tmp_path / "options.yaml"]
    run(cli, *args)
    nominal = kincal.load_robot(nominal_path)
    identified, report = kincal.identify(nominal, kincal.load_dataset(simulated), method, options)
    # The whole robot file, every digit, and the report's numbers.
    assert identified.to_yaml() == (tmp_path / "id.yaml").read_text()
    stage = json.loads((tmp_path / "report.json").read_text())["stages"][0]
    for key in ("status", "iterations", "initial_rms_m", "final_rms_m", "num_measurements", "fixed_parameters"):
        assert report[key] == stage[key], key
    assert [p["value"] for p in report["parameters"]] == [p["value"] for p in stage["parameters"]]

    run(cli, "predict", "--robot", tmp_path / "id.yaml", "--nominal", nominal_path, "--data", simulated,
        "--out", tmp_path / "pred.csv")
    header, rows = numbers((tmp_path / "pred.csv").read_text())
    assert header[:3] == ["x_mm", "y_mm", "z_mm"]
    predicted = kincal.predict(kincal.load_robot(tmp_path / "id.yaml"), kincal.load_dataset(simulated), nominal)
    # The file holds the shortest text t with float(t) * to_si == the prediction, or, when there is none,
    # the 17 significant digits of prediction / to_si (framework/units.h, FormatInUnit).
    printed = np.array([[float(v) for v in row[:3]] for row in rows])
    assert ((printed * MM == predicted) | (printed == predicted / MM)).all()


def test_compensate_matches_kincal_compensate(cli, robots, tmp_path):
    nominal_path, truth_path = robots / "seed_nominal.yaml", robots / "seed_identified.yaml"
    targets = np.array([[600.5, -120.25, 310.0], [550.0, 100.0, 420.125], [480.0, 20.0, 500.0]])
    (tmp_path / "targets.csv").write_text("x_mm,y_mm,z_mm\n" + "".join(
        ",".join(repr(float(v)) for v in row) + "\n" for row in targets))
    run(cli, "compensate", "--nominal", nominal_path, "--identified", truth_path, "--targets",
        tmp_path / "targets.csv", "--method", "jacobian", "--out", tmp_path / "joints.csv")
    header, rows = numbers((tmp_path / "joints.csv").read_text())
    result = kincal.compensate(kincal.load_robot(nominal_path), kincal.load_robot(truth_path), targets * MM,
                               "jacobian")
    assert header[:6] == [f"q{i}_deg" for i in range(1, 7)]
    # std::to_chars: the shortest text that reads back to q / to_si exactly.
    assert np.array_equal(result["q_command"] / DEG, np.array([[float(v) for v in row[:6]] for row in rows]))
    assert np.array_equal(result["encoders"], np.array([[int(v) for v in row[6:12]] for row in rows]))
    assert result["status"] == [row[12] for row in rows]


def test_errors_carry_the_command_lines_message(cli, robots, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text((robots / "seed_nominal.yaml").read_text().replace("convention: mdh", "convention: mdhh"))
    done = subprocess.run([str(cli), "fk", str(bad), "--q=0,0,0,0,0,0"], capture_output=True, text=True)
    assert done.returncode == 2
    with pytest.raises(kincal.Error) as error:
        kincal.load_robot(bad)
    assert done.stderr == "kincal: " + str(error.value) + "\n"

    missing = tmp_path / "missing.csv"
    done = subprocess.run([str(cli), "predict", "--robot", str(robots / "seed_nominal.yaml"), "--data", str(missing),
                           "--out", str(tmp_path / "p.csv")], capture_output=True, text=True)
    assert done.returncode == 2
    with pytest.raises(kincal.Error) as error:
        kincal.load_dataset(missing)
    assert done.stderr == "kincal: " + str(error.value) + "\n"

"""The kincal module on its own: numpy round trips, derivatives against central differences, recovery of
a known truth, and kincal's errors as kincal.Error."""
import math

import numpy as np
import pytest

import kincal


@pytest.fixture
def nominal(robots):
    return kincal.load_robot(robots / "seed_nominal.yaml")


@pytest.fixture
def truth(robots):
    return kincal.load_robot(robots / "seed_identified.yaml")


def test_robot_parameters_round_trip_through_numpy_and_yaml(nominal):
    values = nominal.parameters
    assert values.dtype == np.float64 and values.shape == (len(nominal.parameter_names),)
    assert nominal.parameter("a_2") == pytest.approx(0.2475, abs=0)  # 247.5 mm in the file
    changed = values + 1e-4
    nominal.parameters = changed
    assert np.array_equal(nominal.parameters, changed)
    mask = nominal.free_mask
    mask[0] = False
    nominal.free_mask = mask
    assert not nominal.free_mask[0] and nominal.free_mask[1:].all()
    again = kincal.parse_robot(nominal.to_yaml())
    assert np.array_equal(again.parameters, changed)  # every digit kept
    assert again.parameter_names == nominal.parameter_names


def test_robot_copy_is_independent(nominal):
    other = nominal.copy()
    other.set_parameter("d_3", 0.5)
    assert nominal.parameter("d_3") != 0.5 and other.parameter("d_3") == 0.5


def test_fk_is_the_last_frame_pose_and_a_rigid_transform(truth):
    q = np.radians([10, -20, 30, 40, -50, 60])
    T = truth.fk(q)
    assert T.shape == (4, 4)
    assert np.allclose(T[:3, :3].T @ T[:3, :3], np.eye(3), atol=1e-12)
    assert np.array_equal(T[3], [0, 0, 0, 1])
    frames = truth.frame_poses(q)
    assert frames.shape == (truth.dof + 2, 4, 4)
    assert np.allclose(frames[-1], T, atol=1e-15)


def test_joint_jacobian_matches_central_differences(truth):
    q = np.radians([10, -20, 30, 40, -50, 60])
    point = np.array([0.01, 0.02, 0.03])
    J = truth.joint_jacobian(q, point)
    assert J.shape == (6, truth.dof)
    h = 1e-6
    for i in range(truth.dof):
        dq = np.zeros(truth.dof)
        dq[i] = h
        Tp, Tm = truth.fk(q + dq), truth.fk(q - dq)
        dp = (Tp[:3, :3] @ point + Tp[:3, 3] - Tm[:3, :3] @ point - Tm[:3, 3]) / (2 * h)
        assert np.allclose(J[:3, i], dp, atol=1e-8)


def test_parameter_jacobian_matches_central_differences(truth):
    q = np.radians([5, 15, -25, 35, 45, -55])
    J = truth.parameter_jacobian(q)
    values = truth.parameters
    assert J.shape == (6, values.size)
    h = 1e-7
    for k in range(values.size):
        plus, minus = values.copy(), values.copy()
        plus[k] += h
        minus[k] -= h
        truth.parameters = plus
        p_plus = truth.fk(q)[:3, 3]
        truth.parameters = minus
        p_minus = truth.fk(q)[:3, 3]
        assert np.allclose(J[:3, k], (p_plus - p_minus) / (2 * h), atol=1e-7), truth.parameter_names[k]
    truth.parameters = values


def test_dataset_round_trip_to_numpy_and_back(nominal, truth, tmp_path):
    simulated = kincal.simulate(nominal, truth, protocol="random", poses=25, noise=10e-6, seed=4, orientation=True)
    simulated.save(tmp_path / "data.csv")
    data = kincal.load_dataset(tmp_path / "data.csv")
    columns = data.to_numpy()
    assert columns["q"].shape == (25, 6) and columns["p"].shape == (25, 3)
    assert columns["orientation"].shape == (25, 4) and columns["encoders"].dtype == np.int64
    # File -> numpy -> Dataset -> file: the same text, every digit.
    rebuilt = kincal.Dataset(columns["q"], columns["p"], orientation=columns["orientation"],
                             encoders=columns["encoders"], length_unit=data.length_unit,
                             angle_unit=data.angle_unit)
    assert rebuilt.to_csv() == data.to_csv()
    # Numbers made in radians are written in degrees with every digit they need (17 at most).
    assert np.allclose(columns["q"], simulated.q, rtol=1e-15, atol=0)
    assert np.array_equal(columns["encoders"], simulated.to_numpy()["encoders"])


def test_dataset_columns_split_and_subsets():
    q = np.radians(np.arange(24.0).reshape(4, 6))
    p = np.arange(12.0).reshape(4, 3) * 1e-3
    data = kincal.Dataset(q, p, marker=["A", "B", "A", "B"], split=["train", "test", "train", "test"],
                          session=[0, 1, 0, 1])
    assert len(data) == 4 and data.dof == 6
    assert len(data.subset("train")) == 2 and len(data.select_rows([3, 0])) == 2
    assert np.array_equal(data.select_rows([3, 0]).p, p[[3, 0]])
    columns = data.to_numpy()
    assert columns["marker"] == ["A", "B", "A", "B"] and list(columns["session"]) == [0, 1, 0, 1]
    read = kincal.parse_dataset(data.to_csv())
    assert np.array_equal(read.q, q) and np.array_equal(read.p, p)


def test_dataset_rows_of_every_instrument_expose_kind_fixture_and_value():
    # One file with every kind (docs/instruments.md): a point, a partial point (z only), a distance to a
    # pivot, a plane contact and a socket.
    text = ("q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,distance_mm,pivot,plane,point\n"
            "10,20,30,0,45,0,612.5,-20.25,431,,,,\n"
            "15,25,30,0,45,0,,,300,,,,\n"
            "20,20,35,0,40,0,,,,702.125,P1,,\n"
            "25,20,35,0,40,0,,,,,,table,\n"
            "30,20,35,0,40,0,,,,,,,socket\n")
    data = kincal.parse_dataset(text)
    assert data.kind == ["point", "point", "distance", "plane", "fixed_point"]
    assert data.fixture == ["", "", "P1", "table", "socket"]
    assert data.distance[2] == pytest.approx(0.702125, rel=1e-15)
    assert np.isnan(data.distance[[0, 1, 3, 4]]).all()
    p = data.p
    assert p[0] == pytest.approx([0.6125, -0.02025, 0.431], rel=1e-15)
    assert np.isnan(p[1, :2]).all() and p[1, 2] == pytest.approx(0.3, rel=1e-15)
    assert np.isnan(p[2:]).all()  # a distance, a contact and a socket read no coordinate
    columns = data.to_numpy()
    assert columns["kind"] == data.kind and columns["fixture"] == data.fixture
    assert np.array_equal(columns["distance"], data.distance, equal_nan=True)
    # numpy -> Dataset -> file: the same text.
    rebuilt = kincal.Dataset(columns["q"], columns["p"], kind=columns["kind"], fixture=columns["fixture"],
                             distance=columns["distance"])
    assert rebuilt.to_csv() == data.to_csv()
    assert rebuilt.kind == data.kind and np.array_equal(rebuilt.p, p, equal_nan=True)
    # A file of full points has no such columns.
    assert "kind" not in kincal.parse_dataset(text.split("\n15,")[0] + "\n").to_numpy()
    with pytest.raises(kincal.Error, match="kind"):
        kincal.Dataset(columns["q"], columns["p"], kind=["point", "point", "ruler", "plane", "fixed_point"],
                       fixture=columns["fixture"], distance=columns["distance"])


def test_simulated_distances_and_contacts_read_back_with_their_pivots_and_planes(nominal, truth, tmp_path):
    for instrument, kind, prefix in (("distance", "distance", "P"), ("plane", "plane", "plane")):
        simulated = kincal.simulate(nominal, truth, protocol="random", poses=12, noise=0.0, seed=3,
                                    instrument=instrument)
        simulated.save(tmp_path / f"{instrument}.csv")
        data = kincal.load_dataset(tmp_path / f"{instrument}.csv")
        assert data.kind == [kind] * 12
        assert all(name.startswith(prefix) for name in data.fixture) and len(set(data.fixture)) == 3
        assert np.isnan(data.p).all()
        assert np.isfinite(data.distance).all() == (kind == "distance")
        assert np.array_equal(data.distance, simulated.distance, equal_nan=True)

def test_methods_lists_every_registry():
    methods = kincal.methods()
    assert "mdh" in methods["models"]
    names = [e["name"] for e in methods["estimators"]]
    assert "least_squares" in names and "geometric" in names
    assert "jacobian" in [e["name"] for e in methods["compensators"]]


def test_identify_recovers_the_truth_and_compensation_reaches_targets(nominal, truth):
    train = kincal.simulate(nominal, truth, protocol="random", poses=60, seed=1)
    test = kincal.simulate(nominal, truth, protocol="random", poses=40, seed=2)
    identified, report = kincal.identify(nominal, train, "least_squares", {"max_iterations": 50})
    assert report["estimator"] == "least_squares" and report["status"] == "converged"
    assert report["final_rms_m"] < 1e-9 < report["initial_rms_m"]
    before = kincal.evaluate(nominal, test)["position_stats"]["rms"]
    after = kincal.evaluate(identified, test, nominal=nominal)["position_stats"]["rms"]
    assert before > 1e-4 and after < 1e-8  # noise-free data: the truth's predictions

    rng = np.random.default_rng(7)
    q = np.radians(rng.uniform(-40, 40, size=(5, 6)))
    q[:, 4] = np.radians(rng.uniform(20, 60, size=5))  # the wrist away from its singularity (q5 = 0)
    targets = np.array([truth.fk(qi) for qi in q])
    result = kincal.compensate(nominal, identified, targets, "jacobian")
    assert result["status"] == ["converged"] * 5
    assert result["q_command"].shape == (5, 6) and result["encoders"].shape == (5, 6)
    for qa, target in zip(result["q_actual"], targets):
        assert np.allclose(truth.fk(qa), target, atol=1e-7)


def test_pipeline_report_has_every_stage(nominal, truth):
    data = kincal.simulate(nominal, truth, protocol="sweep", noise=5e-6, seed=3)
    _, report = kincal.identify(nominal, data, "geometric,ratio_regression")
    assert [s["estimator"] for s in report["stages"]] == ["geometric", "ratio_regression"]
    assert report["brief"].startswith("ratio_regression")


def test_errors_are_kincal_errors_with_the_one_line_message(nominal, tmp_path):
    assert issubclass(kincal.Error, ValueError)
    with pytest.raises(kincal.Error, match="no_such_robot.yaml"):
        kincal.load_robot(tmp_path / "no_such_robot.yaml")
    with pytest.raises(kincal.Error) as error:
        kincal.parse_robot("name: x\nconvention: mdh\nunits: {length: mm, angle: deg}\njoints:\n  - {alpha: 0, a: 0, thta: 0, d: 0}\n",
                           "bad.yaml")
    assert str(error.value).startswith("bad.yaml:5:") and "\n" not in str(error.value)
    with pytest.raises(kincal.Error, match="expected 6 values, got 2"):
        nominal.fk(np.zeros(2))
    with pytest.raises(kincal.Error, match="unknown method 'nope'"):
        kincal.identify(nominal, kincal.simulate(nominal, nominal, poses=5, protocol="random"), "nope")
    with pytest.raises(kincal.Error, match="max_iteration"):
        kincal.identify(nominal, kincal.simulate(nominal, nominal, poses=5, protocol="random"), "least_squares",
                        {"max_iteration": 3})
    with pytest.raises(kincal.Error):
        kincal.Dataset(np.zeros((3, 6)), np.zeros((2, 3)))


def test_run_study_writes_the_report(robots, tmp_path):
    study = tmp_path / "study.yaml"
    study.write_text(f"""name: python_study
robots: {{nominal: {robots / 'seed_nominal.yaml'}, truth: {robots / 'seed_identified.yaml'}}}
datasets:
  - {{name: random, simulate: {{protocol: random, poses: 40, noise: 10um}}}}
estimators: [least_squares]
compensators: [jacobian]
validation:
  - {{name: few, random_targets: 5}}
""")
    summary = kincal.run_study(study, tmp_path / "out", threads=1)
    assert summary["items_run"] == summary["items_total"] == 2  # the baseline `none` and least_squares
    assert (tmp_path / "out" / "report.md").exists()


def ratios(path):
    """The `drives: ratio: [...]` list of a robot file, read as text."""
    line = next(l for l in path.read_text().splitlines() if l.strip().startswith("ratio:"))
    return np.array([float(v) for v in line.split("[")[1].split("]")[0].split(",")])


def test_actual_angles_apply_the_drive_ratios(nominal, truth, robots):
    q = np.radians([10, -20, 30, 40, -50, 60])
    assert np.array_equal(nominal.actual_angles(q), q)  # its own controller, no joint level: the readings
    actual = truth.actual_angles(q, controller=nominal)
    # The truth turns by K_nominal / K_truth of what the controller commands (METHOD.md section 3).
    expected = q * ratios(robots / "seed_nominal.yaml") / ratios(robots / "seed_identified.yaml")
    assert np.allclose(actual, expected, rtol=1e-14, atol=0) and not np.allclose(actual, q, rtol=1e-4)

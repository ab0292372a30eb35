"""Methods from outside kincal in Python: estimators and compensators registered from Python run in
identify, compensate and run_study beside the C++ ones, with the same report rows; an exception in one
fails its work item with the Python message, never the process."""
import csv

import numpy as np
import pytest

import kincal


class DelegatingEstimator:
    """least_squares through kincal.identify: the same arithmetic as the built-in, through Python."""

    def __init__(self, options):
        self.options = options

    def estimate(self, start, data):
        robot, report = kincal.identify(start, data, "least_squares", options=self.options or None)
        return robot, report  # the report's keys (status, message, iterations, parameters, ...) are read back


class NewtonCompensator:
    """Newton steps (at most 0.1 rad) in numpy on the identified arm's 6-D pose error (position / 0.5 m,
    rotation log), the `jacobian` compensator's residual."""

    def __init__(self, options):
        self.iterations = int(options.get("iterations", 100))

    def prepare(self, nominal, identified):
        self.robot = identified

    def compensate(self, target, seed):
        q = np.array(seed, dtype=float)
        for _ in range(self.iterations):
            T = self.robot.fk(q)
            R = target[:3, :3] @ T[:3, :3].T
            angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
            axis = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
            w = axis * (0.5 if angle < 1e-12 else angle / (2 * np.sin(angle)))
            e = np.concatenate([(target[:3, 3] - T[:3, 3]) / 0.5, w])
            J = self.robot.joint_jacobian(q)
            J[:3] /= 0.5
            dq = np.linalg.lstsq(J, e, rcond=None)[0]
            dq *= min(1.0, 0.1 / np.max(np.abs(dq)))  # at most 0.1 rad per step: no overshoot far from the solution
            q += dq
            if np.max(np.abs(dq)) < 1e-11:
                return q, "converged"
        return q, "iteration_limit"


class Failing:
    def __init__(self, options):
        pass

    def estimate(self, start, data):
        raise ValueError("deliberate failure in a Python estimator")

    def compensate(self, target, seed):
        raise RuntimeError("deliberate failure in a Python compensator")


@pytest.fixture(scope="module", autouse=True)
def registered():
    kincal.register_estimator("py_least_squares", DelegatingEstimator, "least_squares through Python")
    kincal.register_estimator("py_failing", Failing)
    kincal.register_compensator("py_newton", NewtonCompensator, "Newton steps in numpy")
    kincal.register_compensator("py_failing", Failing)


def rows(path, **match):
    with open(path) as f:
        return [r for r in csv.DictReader(f) if all(r[k] == v for k, v in match.items())]


def test_registered_methods_are_listed_and_names_are_not_taken_twice():
    methods = kincal.methods()
    assert "py_least_squares" in [m["name"] for m in methods["estimators"]]
    assert "py_newton" in [m["name"] for m in methods["compensators"]]
    with pytest.raises(ValueError, match="taken"):
        kincal.register_estimator("least_squares", DelegatingEstimator)
    with pytest.raises(ValueError, match="taken"):
        kincal.register_compensator("py_newton", NewtonCompensator)


def test_python_estimator_in_identify_equals_the_builtin(robots):
    nominal = kincal.load_robot(robots / "seed_nominal.yaml")
    truth = kincal.load_robot(robots / "seed_identified.yaml")
    data = kincal.simulate(nominal, truth, protocol="random", poses=50, noise=5e-6, seed=4)
    built_in, _ = kincal.identify(nominal, data, "least_squares")
    through_python, report = kincal.identify(nominal, data, "py_least_squares")
    assert np.array_equal(built_in.parameters, through_python.parameters)
    assert report["estimator"] == "py_least_squares" and report["status"] == "converged"
    with pytest.raises(RuntimeError, match="deliberate failure in a Python estimator"):
        kincal.identify(nominal, data, "py_failing")


def test_python_methods_in_run_study_beside_the_builtins(robots, tmp_path):
    study = tmp_path / "study.yaml"
    study.write_text(f"""name: python methods
seed: 5
robots: {{nominal: {robots / 'seed_nominal.yaml'}, truth: {robots / 'seed_identified.yaml'}}}
datasets:
  - {{name: random, simulate: {{protocol: random, poses: 50, noise: 5um}}}}
estimators: [least_squares, py_least_squares, py_failing]
compensators: [analytic_derivative, jacobian, py_newton, py_failing]
validation:
  - {{name: few, random_targets: 8}}
""")
    summary = kincal.run_study(study, tmp_path / "out", threads=2)
    assert summary["items_run"] == summary["items_total"] == 4  # none and the three estimators
    results = tmp_path / "out" / "results.csv"

    def key(r):
        return {k: v for k, v in r.items() if k not in ("item", "estimator")}

    built_in = rows(results, estimator="least_squares")
    python = rows(results, estimator="py_least_squares")
    assert [key(r) for r in built_in] == [key(r) for r in python]  # the same report rows, every digit
    params = tmp_path / "out" / "parameters.csv"
    assert [key(r) for r in rows(params, estimator="least_squares")] == \
        [key(r) for r in rows(params, estimator="py_least_squares")]

    newton = rows(results, estimator="least_squares", compensator="py_newton")[0]
    jacobian = rows(results, estimator="least_squares", compensator="jacobian")[0]
    assert int(newton["converged"]) >= 7 and int(jacobian["converged"]) == 8
    assert float(newton["position_error_p50_mm"]) == pytest.approx(float(jacobian["position_error_p50_mm"]), abs=1e-6)

    failed = rows(results, estimator="py_failing")
    assert failed and all(r["note"].endswith("ValueError: deliberate failure in a Python estimator") for r in failed)
    failing_compensator = rows(results, estimator="least_squares", compensator="py_failing")
    assert failing_compensator and "deliberate failure in a Python compensator" in failing_compensator[0]["note"]


def test_python_compensator_in_compensate(robots):
    nominal = kincal.load_robot(robots / "seed_nominal.yaml")
    truth = kincal.load_robot(robots / "seed_identified.yaml")
    rng = np.random.default_rng(2)
    targets = np.array([truth.fk(np.radians(rng.uniform(-30, 30, 6))) for _ in range(5)])
    ours = kincal.compensate(nominal, truth, targets, "py_newton")
    built_in = kincal.compensate(nominal, truth, targets, "jacobian")
    assert all(s == "converged" for s in ours["status"])
    assert np.max(ours["position_error"]) < 1e-9
    same = np.max(np.abs(ours["q_actual"] - built_in["q_actual"]), axis=1) < 1e-2
    assert same.sum() >= 4
    assert np.allclose(ours["q_actual"][same], built_in["q_actual"][same], atol=1e-9)
    with pytest.raises(RuntimeError, match="deliberate failure in a Python compensator"):
        kincal.compensate(nominal, truth, targets, "py_failing")

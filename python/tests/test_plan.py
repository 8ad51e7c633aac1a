"""Plans, trajectories and simulations from Python against the C library's: the same
trajectory bytes as `elasticarm plan -o`, the same FE transient as `elasticarm
simulate`, and errors that say what and where."""

import json
import os

import numpy as np
import pytest

import elasticarm as ea

from conftest import ARM, SRC, cli, example

PAPER_LINE = {
    "name": "paper-line",
    "arm_file": ARM,
    "payload_factor": 0.0,
    "start": {"tip": [0.3, -0.2]},
    "goal": {"tip": [0.6, -0.2]},
    "path": "line",
    "objective": "min_time",
    "knots": 100,
}


def read(path):
    with open(path, "rb") as f:
        return f.read()


def strip_run_id(b):
    return b"".join(l for l in b.splitlines(True) if not l.startswith(b"# run_id: "))


@pytest.mark.parametrize("task,cli_args", [
    ("paper-line.yaml", ()),
    ("paper-line-rest.yaml", ()),
    ("paper-line-rest.yaml", ("--refine",)),
])
def test_trajectory_bytes_equal_the_clis(tmp_path, task, cli_args):
    c_out, py_out = tmp_path / "c.csv", tmp_path / "py.csv"
    cli("plan", example(task), "-o", c_out, *cli_args, "--quiet")
    p = ea.plan(example(task), refine=True if cli_args else None)
    p.write(py_out, summary=tmp_path / "py.json")
    # the same bytes but for the run id, new in every run (docs/trajectory-format.md)
    assert strip_run_id(read(py_out)) == strip_run_id(read(c_out))
    summary_py = json.loads(read(tmp_path / "py.json"))
    assert b"# run_id: " + summary_py["run_id"].encode() + b"\n" in read(py_out)
    summary = json.loads(read(tmp_path / "py.json"))
    assert summary["duration_s"] == pytest.approx(p.duration_s, rel=1e-15)
    if cli_args:
        assert p.refine.converged and p.refine.residual_peak_m < p.refine.residual_peak_before_m


def test_at_rest_checked_by_the_fe_by_default():
    # as `elasticarm plan`: the at-rest plan is checked by the FE (within 0.5 mm: no
    # refinement needed on the paper line, 0.23 mm); refine=False plans without the check
    p = ea.plan(example("paper-line-rest.yaml"))
    assert p.refine is not None and p.refine.converged
    assert p.refine.residual_peak_m <= 5e-4
    assert ea.plan(example("paper-line-rest.yaml"), refine=False).refine is None


def test_refine_by_the_nonlinear_model(tmp_path):
    # refine_by="model_only": the at-rest plan brought to rest by the nonlinear reduced model,
    # no FE transient; the same bytes as `plan --refine-by model_only`, and the FE at its
    # converged settings (an independent measure) finds it at rest
    c_out, py_out = tmp_path / "c.csv", tmp_path / "py.csv"
    cli("plan", example("paper-line-rest.yaml"), "-o", c_out, "--refine-by", "model_only",
        "--quiet")
    p = ea.plan(example("paper-line-rest.yaml"), refine_by="model_only")
    p.write(py_out, summary=tmp_path / "py.json")
    # the same plan to rounding: the model's band solves run in the BLAS the process loaded
    # first (numpy's here), which moves the last digits (1e-13 m; accelerations 5e-8)
    c_rows = [l for l in read(c_out).decode().splitlines() if not l.startswith("#")][1:]
    py_rows = [l for l in read(py_out).decode().splitlines() if not l.startswith("#")][1:]
    assert len(c_rows) == len(py_rows)
    for a, b in zip(c_rows, py_rows):
        assert [float(x) for x in b.split(",")] == pytest.approx(
            [float(x) for x in a.split(",")], rel=1e-6, abs=1e-6)
    summary = json.loads(read(tmp_path / "py.json"))
    assert summary["refine"]["by"] == "model_only" and not summary["fe_check"]["checked"]
    assert p.refine.converged and p.refine.residual_peak_m < 5e-5
    sim = ea.simulate(p, scheme="genalpha", dt=5e-4, settle=3.0, damping_ratio=0.0,
                      history=False)
    assert sim.residual_peak_m < 1e-3
    with pytest.raises(ValueError):
        ea.plan(example("paper-line-rest.yaml"), refine_by="exact")


def _paper_line_rest_with(tmp_path, dynamics):
    """paper-line-rest.yaml with its dynamics block replaced; the arm file by its path."""
    text = read(example("paper-line-rest.yaml")).decode()
    text = text.replace("../../data/elasticarm.yaml", ARM)
    text = text[:text.index("dynamics:")] + dynamics
    path = tmp_path / "task.yaml"
    path.write_text(text)
    return path


def test_a_broken_promise_of_rest_raises_where_the_cli_exits_3(tmp_path):
    # one evaluation (the FE check itself, 0.23 mm) against a 1 um tolerance: the
    # refinement stops short of its bound; the CLI writes the plan and exits 3
    task = _paper_line_rest_with(tmp_path, "dynamics:\n  modes: 2\n  residual_m: 0\n"
                                 "  refine:\n    tolerance_m: 1.0e-6\n    max_evaluations: 1\n")
    r = cli("plan", task, "-o", tmp_path / "c.csv", "--quiet", check=False)
    assert r.returncode == 3 and "does not keep its promise of rest" in r.stderr
    with pytest.raises(ea.PromiseError) as e:
        ea.plan(task)
    assert "exceeds the bound 0.001 mm after 1 evaluation" in str(e.value)
    p = e.value.plan  # the plan is there to look at, as the CLI's file is
    assert not p.refine.converged and p.refine.residual_peak_m > 1e-4
    p.write(tmp_path / "py.csv")
    assert strip_run_id(read(tmp_path / "py.csv")) == strip_run_id(read(tmp_path / "c.csv"))
    assert ea.plan(task, refine=False).refine is None  # no check: no promise judged


def test_a_residual_bound_is_refined_to_and_checked_as_the_cli_does(tmp_path):
    # the diagonal (0.25, -0.45) -> (0.6, -0.3) at payload factor 0.25 allowed 5 mm: the
    # model's plan leaves about 9.8 mm in the FE; the default check refines it to the bound,
    # then one FE transient at --verify's settings gives the verdict (the CLI: exit 0)
    text = read(example("paper-line-rest.yaml")).decode().replace("../../data/elasticarm.yaml", ARM)
    text = (text.replace("tip: [0.3, -0.2]", "tip: [0.25, -0.45]")
            .replace("tip: [0.6, -0.2]", "tip: [0.6, -0.3]")
            .replace("payload_factor: 0.0", "payload_factor: 0.25")
            .replace("residual_m: 0", "residual_m: 0.005"))
    task = tmp_path / "diagonal.yaml"
    task.write_text(text)
    cli("plan", task, "-o", tmp_path / "c.csv", "--quiet")
    p = ea.plan(task)
    assert p.refine.converged and p.refine.residual_peak_before_m > 0.008
    assert p.verify.passed and p.verify.residual_bound_m == 0.005
    assert p.verify.residual_peak_m <= 0.005
    p.write(tmp_path / "py.csv")
    assert strip_run_id(read(tmp_path / "py.csv")) == strip_run_id(read(tmp_path / "c.csv"))
    # unchecked on request: the model's own plan, which the FE would refuse
    q = ea.plan(task, refine=False)
    assert q.refine is None and q.verify is None
    with pytest.raises(ea.PromiseError) as e:
        ea.plan(task, refine=False, verify=True)
    assert "exceeds the bound 5 mm" in str(e.value) and e.value.plan.verify.residual_peak_m > 0.008


def test_trajectory_columns_are_the_files(tmp_path):
    p = ea.plan(example("paper-line.yaml"))
    tr = p.trajectory
    assert tr.columns[0] == "t_s" and "tip_x_m" in tr.columns and len(tr.columns) == 18
    assert tr.t_s[0] == 0 and tr.t_s[-1] == pytest.approx(p.duration_s, rel=1e-12)
    assert tr["cable_length_m"] is not None and tr.data.shape == (len(tr), 18)
    # outside the code: the tip runs on the straight line from (0.3, -0.2) to (0.6, -0.2) m
    # in the arm's plane (the base frame's x, z at base angle 0)
    np.testing.assert_allclose(tr.tip_z_m, -0.2, atol=1e-9)
    np.testing.assert_allclose(tr.tip_y_m, 0, atol=0)
    assert tr.tip_x_m[0] == pytest.approx(0.3, abs=1e-9)
    assert tr.tip_x_m[-1] == pytest.approx(0.6, abs=1e-9)
    # a file read back and written again is the same bytes
    tr.write(tmp_path / "a.csv")
    back = ea.Trajectory.read(tmp_path / "a.csv")
    np.testing.assert_array_equal(back.data, tr.data)
    back.write(tmp_path / "b.csv")
    assert read(tmp_path / "a.csv") == read(tmp_path / "b.csv")


def test_a_dict_plans_as_its_file(tmp_path):
    a = ea.plan(PAPER_LINE)
    b = ea.plan(example("paper-line.yaml"))
    np.testing.assert_array_equal(a.trajectory.data, b.trajectory.data)
    t = ea.Task.from_dict(dict(PAPER_LINE, knots=40))
    assert t.knots == 40 and t.objective == "min_time" and t.path == "line"
    assert t.start.reach_m == 0.3 and t.goal.height_m == -0.2


def test_changed_limits_plan_longer():
    t = ea.Task.load(example("paper-line.yaml"))
    base = ea.plan(t)
    t.limits.cable_speed_max *= 0.5
    t.check()
    slow = ea.plan(t)
    assert slow.duration_s > base.duration_s


def test_simulate_equals_the_clis(tmp_path):
    traj = tmp_path / "rest.csv"
    p = ea.plan(example("paper-line-rest.yaml"), verify=True)
    p.write(traj)
    c = json.loads(cli("simulate", traj, "--json", "-o", tmp_path / "hist.csv").stdout)
    s = ea.simulate(traj)
    assert s.residual_peak_m == pytest.approx(c["residual_vibration_peak_m"], rel=1e-15)
    assert s.residual_rms_m == pytest.approx(c["residual_vibration_rms_m"], rel=1e-15)
    # the plan's --verify ran the same transient
    assert p.verify.residual_peak_m == s.residual_peak_m
    h = np.loadtxt(tmp_path / "hist.csv", delimiter=",", skiprows=1)
    assert h.shape[0] == len(s.t_s)
    np.testing.assert_allclose(s.tip_x_m, h[:, 1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(s.tip_y_m, h[:, 2], rtol=0, atol=1e-12)
    # the same from the Plan object (its arm) and from the Trajectory
    assert ea.simulate(p, history=False).residual_peak_m == s.residual_peak_m


def test_errors_carry_the_librarys_message(tmp_path):
    with pytest.raises(ea.InfeasibleError) as e:
        ea.plan(example("infeasible-goal.yaml"))
    assert "infeasible-goal.yaml:9:3: goal: outside the workspace" in str(e.value)
    assert e.value.status_name == "EA_ERR_INFEASIBLE"
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: bad\nstart:\n  tip: [0.3, -0.2]\ngoal:\n  tip: [0.6, -0.2]\n"
                   "knots: 2x\n")
    with pytest.raises(ea.InputError) as e:
        ea.Task.load(bad)
    assert str(e.value).startswith(str(bad) + ":6:8: ") and "knots" in str(e.value)
    with pytest.raises(ea.InputError) as e:
        ea.Task.from_dict(dict(PAPER_LINE, objective="fastest"))
    assert "<dict>:" in str(e.value) and "objective" in str(e.value)
    with pytest.raises(ea.InputError) as e:
        ea.Trajectory.read(os.path.join(SRC, "README.md"))
    assert "README.md:3:1: not an elasticarm trajectory" in str(e.value)
    with pytest.raises(ea.InputError) as e:
        ea.Task.load(tmp_path / "missing.yaml")
    assert "missing.yaml" in str(e.value)


def test_study_equals_the_clis(tmp_path):
    spec = {
        "name": "py-study",
        "arm_file": ARM,
        "grid": {"payload_factor": [0.0, 0.25], "EI_Nm2": [0.6, 0.705]},
        "metrics": {
            "torque_map": {"cable_lengths_m": "0.3:0.1:0.6", "cable_angles_deg": "-40:10:0"},
            "path": {"start": [0.3, -0.2], "goal": [0.5, -0.2], "steps": 5},
        },
    }
    spec_file = tmp_path / "study.yaml"
    spec_file.write_text(json.dumps(spec, indent=1))
    cli("study", spec_file, "-o", tmp_path / "c.csv", "--threads", 1, "--quiet")
    r = ea.study(spec, threads=2)
    assert r.csv.encode() == read(tmp_path / "c.csv")
    assert r.info.cases_total == 4 and r.info.cases_failed == 0
    assert "torque_max" in r.metrics() and len(r.value("torque_max")) == 4

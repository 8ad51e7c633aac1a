"""Tasks, the planner, trajectories and their FE simulation (planner/)."""

import json
import math
import os

import numpy as np

from ._core import Arm, Record, default_arm_file
from ._lib import (STATUS, Opaque, PromiseError, check, cpath, error, ffi, lib, nan_to_none,
                   new_error, struct_dict, text)

#: Trajectory columns in file order, with their units ("t_s", "cable_length_m", ...).
COLUMNS = tuple(ffi.string(lib.ea_traj_column_name(c)).decode() for c in range(18))

_OBJECTIVES = {0: "min_time", 1: "min_effort", 2: "min_jerk", 3: "min_vibration"}


def _default_arm_arg(default_arm):
    return cpath(default_arm if default_arm is not None else default_arm_file())


def _point(p):
    return Record(cable_length_m=p.cable_length, cable_angle_rad=p.cable_angle,
                  base_angle_rad=p.base_angle, reach_m=p.reach, height_m=p.height,
                  tension_N=p.p[1], theta0_rad=p.p[2], kappa0_per_m=p.p[3])


class Task:
    """A task spec (ea_task.h, docs/task-format.md): what a plan must do. Load one with
    Task.load(path) or Task.from_dict(d) (the same keys as the YAML file). Read its
    fields as attributes; knots and the limits (task.limits.cable_speed_max, SI) may be
    changed, then task.check() resolves and validates it again."""

    def __init__(self):
        self._o = Opaque("ea_task_t")

    @classmethod
    def load(cls, path, default_arm=None):
        """A task file. Its arm_file is read relative to the task file; a task without
        one uses default_arm (None: default_arm_file())."""
        t = cls()
        err = new_error()
        check(lib.ea_task_load(cpath(path), _default_arm_arg(default_arm), t._o.ptr, err), err)
        return t

    @classmethod
    def from_yaml(cls, yaml_text, name="<string>", default_arm=None):
        """A task file's text (arm_file relative to the working directory)."""
        t = cls()
        b = yaml_text.encode()
        err = new_error()
        check(lib.ea_task_load_string(name.encode(), b, len(b), _default_arm_arg(default_arm),
                                      t._o.ptr, err), err)
        return t

    @classmethod
    def from_dict(cls, spec, name="<dict>", default_arm=None):
        """A task from a dict with the task file's keys, e.g.
        {"start": {"tip": [0.3, -0.2]}, "goal": {"tip": [0.6, -0.2]}, "path": "line"}.
        It is given to the library's YAML loader as JSON, one key per line, so
        messages name name:line:column of that text and the key."""
        return cls.from_yaml(json.dumps(spec, indent=1), name, default_arm)

    def copy(self):
        t = Task()
        ffi.memmove(t._o.buf, self._o.buf, ffi.sizeof(self._o.buf))
        return t

    def check(self):
        """Resolve the points and validate the task (ea_task_check)."""
        err = new_error()
        check(lib.ea_task_check(self._o.ptr, err), err)

    name = property(lambda self: self._o.get("name"))
    file = property(lambda self: self._o.get("file"))
    arm_file = property(lambda self: self._o.get("arm_file"))
    payload_kg = property(lambda self: self._o.get("payload_kg"))
    duration_s = property(lambda self: nan_to_none(self._o.get("duration_s")))
    objective = property(lambda self: ffi.string(lib.ea_task_objective_name(
        self._o.get("objective"))).decode())
    path = property(lambda self: ffi.string(lib.ea_task_path_name(self._o.get("path"))).decode())
    dynamics_modes = property(lambda self: self._o.get("dynamics.modes"))
    start = property(lambda self: _point(self._o.get("start")))
    goal = property(lambda self: _point(self._o.get("goal")))
    #: ea_task_limits_t in place: fields read and write (SI units)
    limits = property(lambda self: self._o.get("limits"))

    @property
    def knots(self):
        return self._o.get("knots")

    @knots.setter
    def knots(self, n):
        self._o.set("knots", int(n))

    @property
    def arm(self):
        """A copy of the task's arm."""
        return Arm._from_c(self._o.field("arm")[0])

    def __repr__(self):
        return "Task(%r, %s, %s path, %d knots)" % (self.name, self.objective, self.path,
                                                    self.knots)


class Trajectory:
    """A trajectory (ea_traj.h, docs/trajectory-format.md): n samples of the columns
    COLUMNS, each an attribute holding a numpy array with its unit in its name
    (traj.t_s, traj.cable_length_m, traj.tip_x_m, ...), data the (n, 18) array, and the
    file's metadata (payload_kg, tip_mass_kg, arm_file, task, status; arm_hash, the
    ea_arm_hash of the arm it was planned for, None when unknown; run_id, the plan run
    that wrote it, "" none)."""

    columns = COLUMNS

    def __init__(self, data, payload_kg=0.0, tip_mass_kg=0.0, arm_file="", task="",
                 status="EA_OK", arm_hash=None, run_id=""):
        data = np.array(data, dtype=float)
        if data.ndim != 2 or data.shape[1] != len(COLUMNS):
            raise ValueError("data: shape (n, %d)" % len(COLUMNS))
        self.data = data
        self.payload_kg = payload_kg
        self.tip_mass_kg = tip_mass_kg
        self.arm_file = arm_file
        self.task = task
        self.status = status
        self.arm_hash = arm_hash
        self.run_id = run_id

    @classmethod
    def _from_c(cls, tr):
        n = tr.n
        data = np.frombuffer(ffi.buffer(tr.data, n * 18 * 8), dtype=float).reshape(n, 18).copy()
        return cls(data, tr.payload_kg, tr.tip_mass_kg, text(tr.arm_file), text(tr.task),
                   text(tr.status), int(tr.arm_hash) if tr.has_arm_hash else None,
                   text(tr.run_id))

    def _to_c(self):
        tr = ffi.gc(ffi.new("ea_traj_t *"), lib.ea_traj_free)
        n = self.data.shape[0]
        check(lib.ea_traj_alloc(tr, n), None, "ea_traj_alloc")
        ffi.memmove(tr.data, np.ascontiguousarray(self.data), n * 18 * 8)
        tr.payload_kg = self.payload_kg
        tr.tip_mass_kg = self.tip_mass_kg
        if self.arm_hash is not None:
            tr.has_arm_hash = 1
            tr.arm_hash = self.arm_hash
        for field, value, size in (("arm_file", self.arm_file, 4096), ("task", self.task, 512),
                                   ("status", self.status, 64), ("run_id", self.run_id, 64)):
            b = value.encode()
            if len(b) >= size:
                raise ValueError("%s: at most %d bytes" % (field, size - 1))
            setattr(tr, field, b)
        return tr

    @classmethod
    def read(cls, path):
        """A trajectory file, or the simple CSV (t_s, cable_length_m, cable_angle_rad):
        ea_traj_read_any (errors name file:line:column)."""
        tr = ffi.gc(ffi.new("ea_traj_t *"), lib.ea_traj_free)
        err = new_error()
        check(lib.ea_traj_read_any(tr, cpath(path), ffi.NULL, err), err)
        return cls._from_c(tr)

    def write(self, path):
        """Write the file atomically (ea_traj_write: the bytes `elasticarm plan -o` writes)."""
        tr = self._to_c()
        err = new_error()
        check(lib.ea_traj_write(tr, cpath(path), err), err)

    def __len__(self):
        return self.data.shape[0]

    def __getitem__(self, column):
        return self.data[:, COLUMNS.index(column)]

    def __getattr__(self, name):
        if name in COLUMNS:
            return self.data[:, COLUMNS.index(name)]
        raise AttributeError(name)

    @property
    def duration_s(self):
        return float(self.data[-1, 0] - self.data[0, 0])

    def __repr__(self):
        return "Trajectory(%d samples, %.6g s, task %r)" % (len(self), self.duration_s,
                                                            self.task)


_REFINE_FIELDS = ("converged", "stop_reason", "n_evals", "duration_before_s",
                  "residual_peak_before_m", "duration_s", "residual_peak_m", "residual_rms_m",
                  "time_s", "message")


class Plan:
    """A converged plan: trajectory (Trajectory), info (the planner's ea_plan_info_t as a
    Record: duration_s, iterations, message, ...), refine (what the FE-in-the-loop
    refinement did, or None), verify (the FE transient of the plan beside the reduced
    model's prediction, or None), task."""

    def __init__(self, task, planner, info, trajectory, refine_c, verify_c):
        self.task = task
        self._pl = planner
        self._info = info
        self._refine = refine_c
        self._verify = verify_c
        self.trajectory = trajectory
        self.info = Record(struct_dict(info[0]))
        self.info["status"] = ffi.string(lib.ea_status_name(info.status)).decode()
        self.info["active"] = [text(info.active[i]) for i in range(info.n_active)]
        self.refine = None
        if refine_c is not None:
            self.refine = Record((k, refine_c.get(k)) for k in _REFINE_FIELDS)
            self.refine["converged"] = bool(self.refine["converged"])
        self.verify = None
        if verify_c is not None:
            v = verify_c
            self.verify = Record(
                status=ffi.string(lib.ea_status_name(v.status)).decode(),
                message=text(v.message), passed=bool(v.passed), failure=text(v.failure),
                residual_bound_m=nan_to_none(v.residual_bound_m),
                residual_peak_m=v.sim.residual_peak,
                residual_rms_m=v.sim.residual_rms, time_to_rest_s=nan_to_none(v.sim.time_to_rest),
                damping_ratio=v.sim.damping_ratio,
                predicted_residual_m=nan_to_none(v.predicted_residual_m),
                predicted_time_to_rest_s=nan_to_none(v.predicted_time_to_rest_s),
                sim=_sim_record(v.sim))

    @property
    def duration_s(self):
        return self.info["duration_s"]

    def write(self, path, summary=None):
        """Write the trajectory file (and the JSON summary, as `elasticarm plan -o PATH
        --summary SUMMARY` does): both carry one new run id (docs/trajectory-format.md),
        so a reader can tell that they belong together."""
        run_id = _run_id()
        self.trajectory.run_id = run_id
        self.trajectory.write(path)
        if summary is not None:
            self.write_summary(summary, run_id)

    def write_summary(self, path, run_id=None):
        """The JSON summary (ea_plan_summary_write_ex), with the refinement and the
        verification when they ran, and the run id (the trajectory's, else a new one)."""
        err = new_error()
        ref = self._refine.ptr if self._refine is not None else ffi.NULL
        ver = self._verify if self._verify is not None else ffi.NULL
        rid = (run_id or self.trajectory.run_id or _run_id()).encode()
        check(lib.ea_plan_summary_write_ex(self._pl, self._info, ref, ffi.NULL, ver, rid,
                                           cpath(path), err), err)

    def __repr__(self):
        return "Plan(%r, %.6g s, %d knots)" % (self.task.name, self.duration_s,
                                               len(self.trajectory))


def _run_id():
    """A run id as `elasticarm plan` makes them: UTC time, pid and 32 random bits."""
    import time
    return "%s-%d-%08x" % (time.strftime("%Y%m%dT%H%M%SZ", time.gmtime()), os.getpid(),
                           int.from_bytes(os.urandom(4), "little"))


_REFINE_BY = {"fe": 0, "model": 1, "model_only": 2}


def plan(task, *, refine=None, verify=None, knots=None, default_arm=None, refine_by=None):
    """Plan a task as `elasticarm plan` does (ea_planner_alloc, ea_planner_solve from
    cold), with the same checks of what the plan promises.

    task: a Task, a task file's path or a dict. knots: override the task's.
    refine: True runs the FE-in-the-loop refinement of an at-rest plan (ea_plan_refine)
    with the task's dynamics.refine settings; False: no refinement and no check of rest;
    None (default): as the CLI, the task's dynamics.refine, else a plan that ends at rest
    is checked by the FE and refined until its residual is within 0.5 mm (unless the
    task's dynamics.verify is false).
    refine_by: what measures the refinement's candidates (dynamics.refine.by, `plan
    --refine-by`): "fe", "model" (the nonlinear reduced model, then the FE verdict) or
    "model_only" (no FE transient: the plan is not checked by the FE); None: the task's.
    verify: True runs the FE transient of the plan (ea_traj_simulate with its defaults,
    `plan --verify`); False: never; None (default): when the task bounds the residual
    (dynamics.residual_m > 0), as the CLI checks that bound.

    Raises InfeasibleError / SolverError with the planner's message (which constraint,
    at which knot, by how much); the exception's .info holds the solve's info.
    Raises PromiseError (where the CLI exits 3) when a plan was made but the FE says it
    does not keep its promise: the refinement did not bring it within its bound, or the
    FE transient exceeded the residual bound or let the cable go slack. Its .plan is the
    plan (the best one evaluated)."""
    if isinstance(task, dict):
        task = Task.from_dict(task, default_arm=default_arm)
    elif not isinstance(task, Task):
        task = Task.load(task, default_arm=default_arm)
    task = task.copy()
    if knots is not None:
        task.knots = knots
    rest_check = lib.ea_plan_rest_check(task._o.ptr)  # 0 none, 1 at rest, 2 residual bound
    if refine is not None:
        task._o.set("dynamics.refine.enabled", 1 if refine else 0)
    if refine_by is not None:
        if refine_by not in _REFINE_BY:
            raise ValueError("refine_by: %r is not one of fe, model, model_only" % (refine_by,))
        task._o.set("dynamics.refine.by", _REFINE_BY[refine_by])
    # as the CLI: the task's refinement, else the default check of the promise
    default_check = refine is None and (task._o.get("dynamics.refine.enabled") or rest_check)
    if verify is None:
        verify = refine is not False and rest_check == 2
    task.check()
    err = new_error()
    pp = ffi.new("ea_planner_t **")
    check(lib.ea_planner_alloc(task._o.ptr, pp, err), err)
    pl = ffi.gc(pp[0], lib.ea_planner_free)
    info = ffi.new("ea_plan_info_t *")
    st = lib.ea_planner_solve(pl, 0, ffi.NULL, info, err)
    if st != 0:
        _raise_plan(st, text(info.message) or text(err.msg), info)
    ref = None
    if default_check or task._o.get("dynamics.refine.enabled"):
        ref = Opaque("ea_refine_info_t")
        rinfo = ffi.new("ea_plan_info_t *")
        st = (lib.ea_plan_rest_refine(pl, rinfo, ref.ptr, err) if default_check
              else lib.ea_plan_refine(pl, ffi.NULL, rinfo, ref.ptr, err))
        if st != 0:
            _raise_plan(st, "refinement failed: " + ref.get("message"), info)
        # as the CLI: the refined plan's info, the at-rest solve's iterations and times
        for k in ("iterations", "time_total_s", "time_guess_s", "time_statics_s",
                  "time_ipopt_s", "time_rest_s", "between_passes"):
            setattr(rinfo, k, getattr(info, k))
        info = rinfo
    tr = ffi.gc(ffi.new("ea_traj_t *"), lib.ea_traj_free)
    check(lib.ea_planner_trajectory(pl, tr, err), err)
    ver = None
    if verify:
        ver = ffi.new("ea_plan_verify_t *")
        lib.ea_sim_settings_default(ffi.addressof(ver, "settings"))
        verr = new_error()
        ver.status = lib.ea_traj_simulate(task._o.field("arm"), tr, 0.0,
                                          ffi.addressof(ver, "settings"), ffi.NULL,
                                          ffi.addressof(ver, "sim"), verr)
        if ver.status != 0:
            ver.message = ffi.string(verr.msg)
        # the bounds the plan claims, as the CLI's: the task's residual bound, else the
        # refinement's tolerance; the cable taut at the task's tension limit
        residual_m = task._o.get("dynamics.residual_m")
        ver.residual_bound_m = (residual_m if task._o.get("dynamics.modes") > 0 and residual_m > 0
                                else ref.get("settings.tolerance_m") if ref is not None
                                else math.nan)
        ver.tension_bound_N = task._o.get("limits").tension_min
        lib.ea_plan_verify_judge(ver)
        ver.predicted_residual_m = info.predicted_residual_m
        ver.predicted_nonlinear_residual_m = math.nan  # the CLI's --verify computes it
        ver.predicted_time_to_rest_s = (info.predicted_time_to_rest_s
                                        if math.isfinite(info.predicted_residual_m)
                                        else math.nan)
    p = Plan(task, pl, info, Trajectory._from_c(tr), ref, ver)
    if ref is not None and not p.refine.converged:
        raise PromiseError(
            "the plan does not keep its promise of %s: the FE residual peak %.4g mm exceeds "
            "the bound %.4g mm after %d evaluation%s (stopped: %s; duration %.6g s)"
            % ("a residual bound" if rest_check == 2 else "rest",
               1e3 * p.refine.residual_peak_m, 1e3 * ref.get("settings.tolerance_m"),
               p.refine.n_evals, "" if p.refine.n_evals == 1 else "s", p.refine.stop_reason,
               p.duration_s), p)
    if ver is not None and not ver.passed:
        raise PromiseError("the FE check of the plan failed: " + text(ver.failure), p)
    return p


def _raise_plan(st, message, info):
    e = error(st, message)
    e.info = Record(struct_dict(info[0]))
    raise e


def _sim_record(si):
    return Record(
        status=ffi.string(lib.ea_status_name(si.status)).decode(), tip_mass_kg=si.tip_mass,
        damping_ratio=si.damping_ratio, duration_s=si.duration,
        simulated_time_s=si.simulated_time, steps=si.steps,
        newton_iterations=si.newton_iterations, residual_peak_m=si.residual_peak,
        residual_rms_m=si.residual_rms, time_to_rest_s=nan_to_none(si.time_to_rest),
        max_tracking_error_m=si.max_tracking_error,
        max_tracking_error_time_s=si.max_tracking_error_time,
        static_offset_start_m=si.static_offset_start, static_offset_end_m=si.static_offset_end,
        final_static_tip_m=list(si.final_static_tip), start_freq_hz=list(si.start_freq_hz),
        tension_min_N=si.tension_min, tension_max_N=si.tension_max,
        energy_drift_max_J=si.energy_drift_max, wall_time_s=si.wall_time_s)


_SCHEMES = {"energy": 0, "genalpha": 1}
_HISTORY = ("t_s", "tip_x_m", "tip_y_m", "tip_theta_rad", "planned_tip_x_m", "planned_tip_y_m")


def simulate(trajectory, arm=None, *, payload_kg=None, elements=None, scheme=None, dt=None,
             settle=None, damping_ratio=None, rest_tolerance=None, cable="passive",
             history=True):
    """The FE transient of a trajectory (ea_traj_simulate; `elasticarm simulate`): the
    nonlinear FE model driven by the trajectory's shoulder angle and cable, then
    `settle` seconds after the motion. trajectory: a Plan, a Trajectory or a file.
    arm: default the plan's arm, else the arm file the trajectory records, else the
    default arm file. Settings left None keep the library's defaults (ea_sim_settings_default:
    12 elements, generalized-alpha, dt 1 ms, settle 3 s, the arm file's damping).

    Returns a Record: residual_peak_m, residual_rms_m, time_to_rest_s,
    max_tracking_error_m, ... and, with history, the tip history as numpy arrays
    t_s, tip_x_m, tip_y_m, tip_theta_rad, planned_tip_x_m, planned_tip_y_m."""
    if isinstance(trajectory, Plan):
        if arm is None:
            arm = trajectory.task.arm
        trajectory = trajectory.trajectory
    elif not isinstance(trajectory, Trajectory):
        trajectory = Trajectory.read(trajectory)
    if arm is None:
        if trajectory.arm_file:
            if not os.access(trajectory.arm_file, os.R_OK):
                raise error(STATUS["EA_ERR_INPUT"], "the trajectory records the arm file '%s', which cannot be read "
                            "here: give the arm" % trajectory.arm_file)
            arm = Arm.load(trajectory.arm_file)
        else:
            arm = Arm.load()
    elif not isinstance(arm, Arm):
        arm = Arm.load(arm)
    s = ffi.new("ea_sim_settings_t *")
    lib.ea_sim_settings_default(s)
    if elements is not None:
        s.elements = int(elements)
    if scheme is not None:
        s.scheme = _SCHEMES[scheme]
    for k, v in (("dt", dt), ("settle", settle), ("damping_ratio", damping_ratio),
                 ("rest_tolerance", rest_tolerance)):
        if v is not None:
            setattr(s, k, v)
    if cable not in ("passive", "active"):
        raise ValueError('cable: "passive" or "active"')
    s.cable_active = 1 if cable == "active" else 0
    s.keep_history = 1 if history else 0
    err = new_error()
    check(lib.ea_sim_settings_validate(s, err), err)
    tip_mass = arm.tip_mass(payload_kg) if payload_kg is not None else 0.0
    tr = trajectory._to_c()
    h = ffi.gc(ffi.new("ea_sim_history_t *"), lib.ea_sim_history_free)
    si = ffi.new("ea_sim_info_t *")
    check(lib.ea_traj_simulate(arm._c, tr, tip_mass, s, h, si, err), err)
    out = _sim_record(si)
    if history:
        rows = h.rows
        a = np.frombuffer(ffi.buffer(h.data, rows * 6 * 8), dtype=float).reshape(rows, 6).copy()
        for i, k in enumerate(_HISTORY):
            out[k] = a[:, i]
    return out

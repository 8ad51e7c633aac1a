"""Arms, statics, workspace and natural frequencies (model/, problems/)."""

import math
import os

import numpy as np

from . import _config
from ._lib import check, cpath, ffi, lib, new_error, text

DEG = math.pi / 180.0  # as the CLI's EA__DEG (M_PI / 180.0)


class Record(dict):
    """A dict whose keys read as attributes (r.tension_N == r["tension_N"])."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __dir__(self):
        return list(self.keys()) + dir(dict)


def default_arm_file():
    """The arm file used when none is named: $EA_ARM_FILE, else the one installed
    (or in the source tree) beside this package; None when there is none (the
    built-in values of the paper, ea_arm_default, are then used)."""
    env = os.environ.get("EA_ARM_FILE")
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    path = os.path.normpath(os.path.join(here, _config.DATA_DIR, "elasticarm.yaml"))
    return path if os.path.exists(path) else None


class Arm:
    """Arm parameters (ea_arm_t, ea_arm.h): the paper's Tables 1 and 2 and the
    actuator limits. Fields read and write as attributes in SI units
    (arm.EI, arm.act.cable_speed_max); arm.validate() checks them."""

    def __init__(self):
        object.__setattr__(self, "_c", ffi.new("ea_arm_t *"))
        lib.ea_arm_default(self._c)

    @classmethod
    def load(cls, path=None):
        """An arm file (YAML, data/elasticarm.yaml); None: default_arm_file(),
        or the built-in values when there is none."""
        arm = cls()
        if path is None:
            path = default_arm_file()
            if path is None:
                return arm
        err = new_error()
        check(lib.ea_arm_load(cpath(path), arm._c, err), err)
        return arm

    @classmethod
    def from_yaml(cls, yaml_text, name="<string>"):
        """An arm file's text."""
        arm = cls()
        b = yaml_text.encode()
        err = new_error()
        check(lib.ea_arm_load_string(name.encode(), b, len(b), arm._c, err), err)
        return arm

    @classmethod
    def _from_c(cls, c):
        arm = cls()
        arm._c[0] = c
        return arm

    def copy(self):
        return Arm._from_c(self._c[0])

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        try:
            v = getattr(self._c, name)
        except AttributeError:
            raise AttributeError("ea_arm_t has no field %r" % name) from None
        if name == "damping_ratio":
            return list(v)[: self._c.n_damping]
        return v

    def __setattr__(self, name, value):
        if name == "damping_ratio":
            if len(value) > 6:
                raise ValueError("at most 6 damping ratios")
            self._c.n_damping = len(value)
            for i, z in enumerate(value):
                self._c.damping_ratio[i] = z
            return
        if not hasattr(self._c, name):
            raise AttributeError("ea_arm_t has no field %r" % name)
        setattr(self._c, name, value)

    def validate(self):
        """Raise InputError naming the field, its value and the bound."""
        err = new_error()
        check(lib.ea_arm_validate(self._c, err), err)

    def payload_from_factor(self, factor):
        """Payload [kg] of a payload factor gamma (eq. 17)."""
        return lib.ea_arm_payload_from_factor(self._c, factor)

    def tip_mass(self, payload_kg=0.0):
        """Tip mass m_L = m_h + m_p [kg]."""
        return lib.ea_arm_tip_mass(self._c, payload_kg)

    def to_dict(self):
        d = {n: getattr(self._c, n) for n, _ in ffi.typeof("ea_arm_t").fields
             if n not in ("act", "n_damping", "damping_ratio")}
        d["act"] = {n: getattr(self._c.act, n) for n, _ in ffi.typeof("ea_actuators_t").fields}
        d["damping_ratio"] = self.damping_ratio
        return d

    def __repr__(self):
        return "Arm(L=%g m, EI=%g N m^2, m_hand=%g kg)" % (self._c.length, self._c.EI,
                                                           self._c.m_hand)


def _arm(arm):
    if arm is None:
        return Arm.load()
    if isinstance(arm, Arm):
        return arm
    return Arm.load(arm)  # a path


def _tip_mass(arm, payload_factor, payload_kg):
    if payload_factor is not None and payload_kg is not None:
        raise ValueError("give payload_factor or payload_kg, not both")
    mp = 0.0
    if payload_factor is not None:
        mp = arm.payload_from_factor(payload_factor)
    elif payload_kg is not None:
        mp = payload_kg
    return arm.tip_mass(mp)


class _Shooter:
    def __init__(self, arm, tip_mass):
        p = ffi.new("ea_shooter_t **")
        err = new_error()
        check(lib.ea_shooter_alloc(arm._c, ffi.NULL, p, err), err)
        self.sh = ffi.gc(p[0], lib.ea_shooter_free)
        load = ffi.new("ea_load_t *", {"tip_mass": tip_mass})
        lib.ea_shooter_set_load(self.sh, load)


def _shape_out(values, shape, dtype=float):
    a = np.asarray(values, dtype=dtype).reshape(shape)
    return a[()] if a.ndim == 0 else a


_STATICS_KEYS = ("cable_length_m", "cable_angle_rad", "tension_N", "theta0_rad", "kappa0_per_m",
                 "shoulder_torque_Nm", "tip_x_m", "tip_y_m", "tip_angle_rad", "residual")


def statics(arm=None, *, cable_length=None, cable_angle=None, tip=None, tension=None,
            theta0=None, payload_factor=None, payload_kg=None, on_error="raise"):
    """The arm's static configuration (paper sec. 2, ea_statics_solve) for one of the
    problem statements: cable_length [m] and cable_angle [rad]; tip = (x, y) [m];
    tension [N] and cable_angle; tension and theta0 [rad]. Each solve starts from the
    T = 0 outer edge (the physical branch), as `elasticarm statics` does.

    Arrays broadcast: every value of the result has their shape (scalars give
    floats). on_error="nan" gives NaN (and the status name in "status") where a
    configuration has no solution instead of raising.

    Returns a Record: cable_length_m, cable_angle_rad, tension_N, theta0_rad,
    kappa0_per_m, shoulder_torque_Nm, tip_x_m, tip_y_m, tip_angle_rad, residual,
    iterations, status, tip_mass_kg."""
    arm = _arm(arm)
    if tip is not None:
        t = np.asarray(tip, dtype=float)
        if t.shape[-1:] != (2,):
            raise ValueError("tip: (x, y) [m] pairs, shape (..., 2)")
        a, b, make = t[..., 0], t[..., 1], lib.ea_statics_problem_tip
    elif cable_length is not None and cable_angle is not None:
        a, b, make = cable_length, cable_angle, lib.ea_statics_problem_cable
    elif tension is not None and cable_angle is not None:
        a, b, make = tension, cable_angle, lib.ea_statics_problem_tension_alpha
    elif tension is not None and theta0 is not None:
        a, b, make = tension, theta0, lib.ea_statics_problem_tension_theta0
    else:
        raise ValueError("give cable_length and cable_angle, tip, tension and cable_angle, "
                         "or tension and theta0")
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    shape = a.shape
    tip_mass = _tip_mass(arm, payload_factor, payload_kg)
    sh = _Shooter(arm, tip_mass)
    n = a.size
    cols = {k: np.full(n, np.nan) for k in _STATICS_KEYS}
    iters = np.zeros(n, dtype=int)
    status = []
    sol = ffi.new("ea_statics_solution_t *")
    prob = ffi.new("ea_statics_problem_t *")
    err = new_error()
    for i, (u, v) in enumerate(zip(a.ravel(), b.ravel())):
        prob[0] = make(float(u), float(v))
        st = lib.ea_statics_solve(sh.sh, prob, ffi.NULL, ffi.NULL, sol, err)
        status.append(ffi.string(lib.ea_status_name(st)).decode())
        if st != 0:
            if on_error == "raise":
                check(st, err, None if n == 1 else "point %d" % i)
            continue
        p = sol.p
        cols["cable_length_m"][i] = sol.cable_length
        cols["cable_angle_rad"][i] = p[0]
        cols["tension_N"][i] = p[1]
        cols["theta0_rad"][i] = p[2]
        cols["kappa0_per_m"][i] = p[3]
        cols["shoulder_torque_Nm"][i] = arm._c.EI * p[3]
        cols["tip_x_m"][i] = sol.tip[2]
        cols["tip_y_m"][i] = sol.tip[3]
        cols["tip_angle_rad"][i] = sol.tip[0]
        cols["residual"][i] = sol.residual
        iters[i] = sol.iterations
    out = Record((k, _shape_out(v, shape)) for k, v in cols.items())
    out["iterations"] = _shape_out(iters, shape, int)
    out["status"] = status[0] if not shape else np.array(status).reshape(shape)
    out["tip_mass_kg"] = tip_mass
    return out


def shape(arm=None, *, cable_length, cable_angle, points=50, payload_factor=None,
          payload_kg=None):
    """The beam's centreline at a configuration (ea_shoot_shape): Record of arrays
    s_m, x_m, y_m, theta_rad, kappa_per_m with `points` samples."""
    arm = _arm(arm)
    tip_mass = _tip_mass(arm, payload_factor, payload_kg)
    sh = _Shooter(arm, tip_mass)
    sol = ffi.new("ea_statics_solution_t *")
    prob = ffi.new("ea_statics_problem_t *", lib.ea_statics_problem_cable(cable_length,
                                                                          cable_angle))
    err = new_error()
    check(lib.ea_statics_solve(sh.sh, prob, ffi.NULL, ffi.NULL, sol, err), err)
    arrs = [np.zeros(points) for _ in range(5)]
    ptrs = [ffi.cast("double *", ffi.from_buffer(x)) for x in arrs]
    check(lib.ea_shoot_shape(sh.sh, sol.p, points, *ptrs), None, "ea_shoot_shape")
    return Record(s_m=arrs[0], theta_rad=arrs[1], kappa_per_m=arrs[2], x_m=arrs[3],
                  y_m=arrs[4])


_POINT_KEYS = (("cable_length_m", "cable_length"), ("cable_angle_rad", "alpha"),
               ("tip_x_m", "x"), ("tip_y_m", "y"), ("tension_N", "tension"),
               ("theta0_rad", "theta0"), ("kappa0_per_m", "kappa0"),
               ("shoulder_torque_Nm", "shoulder_torque"), ("residual", "residual"))


def _points(pts, n):
    out = Record((k, np.array([getattr(pts[i], f) for i in range(n)])) for k, f in _POINT_KEYS)
    out["status"] = np.array([ffi.string(lib.ea_status_name(pts[i].status)).decode()
                              for i in range(n)])
    out["admissible"] = np.array([bool(pts[i].admissible) for i in range(n)])
    out["reason"] = np.array([text(pts[i].reason) for i in range(n)])
    return out


def _extremum(e):
    return Record(value_m=e.value, cable_angle_rad=e.alpha, cable_length_m=e.cable_length,
                  tip_x_m=e.x, tip_y_m=e.y,
                  bound=ffi.string(lib.ea_ws_bound_name(e.bound)).decode())


def workspace(arm=None, *, payload_factor=0.0, payload_kg=None, cable_angle_min=-60 * DEG,
              cable_angle_max=10 * DEG, points=71, inner_cable_length=None, limits=True):
    """The workspace for one payload (paper Fig. 3; `elasticarm workspace`): the outer
    (T = 0) and inner (shortest cable) edges at `points` cable angles from
    cable_angle_min to cable_angle_max [rad], and the region's metrics
    (ea_workspace_metrics: area, reach, largest x, lowest y).

    Returns a Record: area_m2, area_error_m2, reach, x_max, y_min (Records with
    value_m and where), outer and inner (Records of arrays: cable_angle_rad,
    cable_length_m, tip_x_m, tip_y_m, tension_N, theta0_rad, kappa0_per_m,
    shoulder_torque_Nm, residual, status, admissible, reason)."""
    arm = _arm(arm)
    if inner_cable_length is None:
        inner_cable_length = arm.act.cable_length_min
    n = int(points)
    if n < 2:
        raise ValueError("points: at least 2")
    # the CLI's grid, in degrees then converted, so both give the same angles
    amin, amax = cable_angle_min / DEG, cable_angle_max / DEG
    alpha = np.array([(amin + (amax - amin) * k / (n - 1)) * DEG for k in range(n)])
    tip_mass = _tip_mass(arm, payload_factor if payload_kg is None else None, payload_kg)
    sh = _Shooter(arm, tip_mass)
    ws = ffi.new("ea_workspace_settings_t *")
    lib.ea_workspace_settings_default(ws)
    ws.alpha_min, ws.alpha_max = amin * DEG, amax * DEG
    ws.inner_cable_length = inner_cable_length
    ws.limits = 1 if limits else 0
    ws.samples = n
    m = ffi.new("ea_workspace_metrics_t *")
    err = new_error()
    check(lib.ea_workspace_metrics(sh.sh, ws, m, err), err)
    ca = ffi.new("double[]", list(alpha))
    outer = ffi.new("ea_config_point_t[]", n)
    inner = ffi.new("ea_config_point_t[]", n)
    lib.ea_workspace_outer(sh.sh, ca, n, outer)
    lib.ea_workspace_inner(sh.sh, inner_cable_length, ca, n, inner)
    return Record(area_m2=m.area, area_error_m2=m.area_error, reach=_extremum(m.reach),
                  x_max=_extremum(m.x_max), y_min=_extremum(m.y_min),
                  outer=_points(outer, n), inner=_points(inner, n), tip_mass_kg=tip_mass)


def frequencies(arm=None, *, cable_length, cable_angle=0.0, payload_factor=None,
                payload_kg=None, modes=3, elements=12, hold="tip"):
    """Natural frequencies of the FE model (paper sec. 3.3; `elasticarm frequencies`)
    at cable_length [m] and cable_angle [rad]: the statics, the FE equilibrium
    holding the tip (hold="tip") or the ODE tension ("tension"), then the modes.
    cable_length may be an array: the Fig. 5 sweep (ea_freq_sweep, each point
    warm-started from the previous one).

    Returns a Record: frequencies_hz (modes values, or an array of shape
    (len(cable_length), modes)), cable_length_m, stable, status; the statics and the
    FE tension per point (tension_N, fe_tension_N)."""
    arm = _arm(arm)
    tip_mass = _tip_mass(arm, payload_factor, payload_kg)
    sh = _Shooter(arm, tip_mass)
    s = ffi.new("ea_fe_settings_t *")
    lib.ea_fe_settings_default(s)
    s.elements = int(elements)
    s.modes = int(modes)
    if hold not in ("tip", "tension"):
        raise ValueError('hold: "tip" or "tension"')
    s.static_hold_tip = 1 if hold == "tip" else 0
    pm = ffi.new("ea_fe_model_t **")
    err = new_error()
    check(lib.ea_fe_model_alloc(arm._c, s, pm, err), err)
    m = ffi.gc(pm[0], lib.ea_fe_model_free)
    load = ffi.new("ea_load_t *", {"tip_mass": tip_mass})
    check(lib.ea_fe_model_set_load(m, load), None, "ea_fe_model_set_load")
    lengths = np.asarray(cable_length, dtype=float)
    if lengths.ndim == 0:
        pt = ffi.new("ea_freq_point_t *")
        st = lib.ea_freq_point(sh.sh, m, float(lengths), cable_angle, ffi.NULL, pt)
        if st != 0:
            stage = ffi.string(pt.stage).decode() if pt.stage != ffi.NULL else ""
            raise _stage_error(st, stage, text(pt.err.msg))
        return Record(frequencies_hz=np.array(list(pt.modes.freq_hz)[: pt.modes.modes]),
                      cable_length_m=float(lengths), cable_angle_rad=cable_angle,
                      stable=bool(pt.modes.stable), tension_N=pt.ode.p[1],
                      fe_tension_N=pt.fe.tension, status="EA_OK")
    n = lengths.size
    pts = ffi.new("ea_freq_point_t[]", n)
    lib.ea_freq_sweep(sh.sh, m, ffi.new("double[]", list(lengths.ravel())), n, cable_angle, pts)
    f = np.full((n, int(modes)), np.nan)
    for i in range(n):
        if pts[i].status == 0:
            f[i, : pts[i].modes.modes] = list(pts[i].modes.freq_hz)[: pts[i].modes.modes]
    return Record(
        frequencies_hz=f, cable_length_m=lengths.ravel().copy(), cable_angle_rad=cable_angle,
        stable=np.array([bool(pts[i].modes.stable) for i in range(n)]),
        tension_N=np.array([pts[i].ode.p[1] for i in range(n)]),
        fe_tension_N=np.array([pts[i].fe.tension for i in range(n)]),
        status=np.array([ffi.string(lib.ea_status_name(pts[i].status)).decode()
                         for i in range(n)]))


def _stage_error(st, stage, msg):
    from ._lib import error
    return error(st, "%s: %s" % (stage, msg) if stage else msg)

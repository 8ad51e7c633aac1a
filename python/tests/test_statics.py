"""Statics, workspace and frequencies from Python against the C library's answers
(the CLI's JSON, printed with 17 digits), and against geometry."""

import math

import numpy as np
import pytest

import elasticarm as ea

from conftest import ARM, cli_json

REL = 1e-15


def close(a, b, rel=REL):
    return abs(a - b) <= rel * max(abs(a), abs(b)) or a == b


@pytest.mark.parametrize("args,kwargs", [
    (("--cable-length", 0.45, "--cable-angle-deg", -25, "--payload-factor", 0.25),
     dict(cable_length=0.45, cable_angle=-25 * ea._core.DEG, payload_factor=0.25)),
    (("--tip", "0.5,-0.2"), dict(tip=(0.5, -0.2))),
    (("--tension", 8, "--cable-angle-deg", -30, "--payload-kg", 0.1),
     dict(tension=8.0, cable_angle=-30 * ea._core.DEG, payload_kg=0.1)),
    (("--tension", 5, "--theta0-deg", 80), dict(tension=5.0, theta0=80 * ea._core.DEG)),
])
def test_statics_equal_the_c_librarys(args, kwargs):
    c = cli_json("statics", "--arm", ARM, "--no-stability", *args)
    p = ea.statics(ARM, **kwargs)
    assert p.status == c["status"] == "EA_OK"
    for key in ("tension_N", "theta0_rad", "kappa0_per_m", "shoulder_torque_Nm",
                "cable_angle_rad", "cable_length_m", "residual"):
        assert close(p[key], c[key]), (key, p[key], c[key])
    assert close(p.tip_x_m, c["tip_m"][0]) and close(p.tip_y_m, c["tip_m"][1])
    assert p.iterations == c["iterations"]
    assert close(p.tip_mass_kg, c["tip_mass_kg"])


def test_statics_arrays_broadcast_and_the_tip_lies_on_the_cable():
    arm = ea.Arm.load(ARM)
    L = np.linspace(0.35, 0.55, 5)
    s = ea.statics(arm, cable_length=L, cable_angle=-0.4)
    assert s.tension_N.shape == (5,) and (s.status == "EA_OK").all()
    # outside the code: the tip is L_c from the cable root along the cable angle
    dx, dy = s.tip_x_m - arm.x_c, s.tip_y_m - arm.y_c
    np.testing.assert_allclose(np.hypot(dx, dy), L, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.arctan2(dy, dx), -0.4, rtol=0, atol=1e-9)
    # each point as the scalar call gives it
    one = ea.statics(arm, cable_length=L[2], cable_angle=-0.4)
    assert one.tension_N == s.tension_N[2]


def test_statics_failure_raises_or_gives_nan():
    with pytest.raises(ea.ElasticarmError) as e:
        ea.statics(ARM, cable_length=0.95, cable_angle=-0.2)
    assert e.value.status_name.startswith("EA_ERR_") and str(e.value)
    s = ea.statics(ARM, cable_length=[0.45, 0.95], cable_angle=-0.2, on_error="nan")
    assert s.status[0] == "EA_OK" and s.status[1] != "EA_OK"
    assert math.isfinite(s.tension_N[0]) and math.isnan(s.tension_N[1])


def test_workspace_equals_the_c_librarys():
    c = cli_json("workspace", "--arm", ARM, "--payload-factors", "0.25", "--points", 21)
    w = ea.workspace(ARM, payload_factor=0.25, points=21)
    cp = c["payloads"][0]
    assert close(w.area_m2, cp["area_m2"])
    assert close(w.reach.value_m, cp["max_reach"]["value_m"])
    assert close(w.x_max.value_m, cp["x_max"]["value_m"])
    assert close(w.y_min.value_m, cp["y_min"]["value_m"])
    assert w.x_max.bound == cp["x_max"]["bound"]
    assert len(w.outer.tip_x_m) == 21 and (w.outer.status == "EA_OK").all()
    # the outer edge is where the tension vanishes
    np.testing.assert_allclose(w.outer.tension_N, 0, atol=1e-9)


def test_frequencies_equal_the_c_librarys():
    c = cli_json("frequencies", "--arm", ARM, "--cable-length", 0.45, "--cable-angle-deg", -25)
    f = ea.frequencies(ARM, cable_length=0.45, cable_angle=-25 * ea._core.DEG)
    cf = c["frequencies_Hz"]
    assert len(f.frequencies_hz) == len(cf) == 3
    for a, b in zip(f.frequencies_hz, cf):
        assert close(a, b), (a, b)
    # the sweep (Fig. 5): the first mode stiffens as the cable shortens
    s = ea.frequencies(ARM, cable_length=np.linspace(0.254, 0.635, 6))
    assert s.frequencies_hz.shape == (6, 3)
    assert (np.diff(s.frequencies_hz[:, 0]) < 0).all()


def test_arm_fields_read_write_and_validate():
    arm = ea.Arm.load(ARM)
    default = ea.Arm()
    assert arm.EI == default.EI and arm.act.cable_speed_max > 0
    arm.EI = -1.0
    with pytest.raises(ea.InputError) as e:
        arm.validate()
    assert "EI" in str(e.value)
    with pytest.raises(AttributeError):
        arm.no_such_field = 1

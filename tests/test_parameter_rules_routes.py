"""One rule per drive-train parameter on every route a value can enter by: the description's
``[joints.actuator]`` rules (gear ratio and Coulomb smoothing > 0; rotor inertia, viscous and
Coulomb friction >= 0) hold for ``with_parameters``, a study's ``[parameters]``,
``[control.plant]``, ``planar-sym move --set`` and a sweep's range, each refused with the
parameter named (before, every route but the description accepted a negative gear ratio or
friction silently: the sizing table then showed negative motor speeds, and a free motion gained
energy from "friction")."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.errors import InputError
from planar_sym.model.parameters import failing, problems

GEARED = ROOT / "examples" / "serial_2dof_geared.toml"
BAD = {"gear_joint1": (-50.0, r"gear_joint1 \(gear ratio\) must be > 0"),
       "vs_joint1": (0.0, r"vs_joint1 \(Coulomb smoothing speed\) must be > 0"),
       "jm_joint2": (-1e-7, r"jm_joint2 \(rotor inertia\) must be >= 0"),
       "fv_joint1": (-0.001, r"fv_joint1 \(viscous friction\) must be >= 0"),
       "fc_joint1": (-0.005, r"fc_joint1 \(Coulomb friction\) must be >= 0")}


@pytest.fixture(scope="module")
def geared():
    return ps.load(GEARED)


@pytest.mark.parametrize("name", BAD)
def test_with_parameters(geared, name):
    value, message = BAD[name]
    with pytest.raises(InputError, match=message):
        geared.with_parameters(**{name: value})
    geared.with_parameters(**{name: 0.0 if name.startswith(("jm", "fv", "fc")) else 1.0})


def test_the_column_rules_agree_with_the_scalar_ones(geared):
    """The sweep's column-wise check (failing) and the message's (problems) on random designs
    around the example's drive, half of them bad in one drive figure."""
    rng = np.random.default_rng(5)
    names = [p.name for p in geared.parameter_list]
    P = np.tile(geared.p, (200, 1))
    for k in range(200):
        name = list(BAD)[k % len(BAD)]
        P[k, names.index(name)] = rng.uniform(-1, 1) * abs(geared.parameters[name] or 1)
    bad = failing(names, P, geared.body_names)
    assert bad.any() and not bad.all()
    for k in range(200):
        assert bad[k] == bool(problems(dict(zip(names, P[k])), geared.body_names)), k


def _study(tmp_path, kind: str, extra: str) -> str:
    text = (ROOT / "planar_sym" / "studies" / f"serial_2dof_cartesian_{kind}.toml").read_text()
    text = text.replace('robot = "serial_2dof"', f'robot = "{GEARED}"')
    path = tmp_path / f"{kind}.toml"
    path.write_text(text.split("[outputs]")[0] + extra)
    return str(path)


def test_a_study_parameter(tmp_path, capsys):
    study = _study(tmp_path, "move", "\n[parameters]\ngear_joint1 = -50\n")
    assert main(["run", study, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "gear_joint1 (gear ratio) must be > 0" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_a_control_plant_parameter(tmp_path, capsys):
    study = _study(tmp_path, "track", "")
    path = Path(study)
    path.write_text(path.read_text().replace("m_link2 = 0.09", "m_link2 = 0.09\nfv_joint1 = -0.001"))
    assert main(["run", study, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "fv_joint1 (viscous friction) must be >= 0" in err and "control.plant" in err


def test_move_set(tmp_path, capsys):
    code = main(["move", str(GEARED), "--joint", "--from", "0,0", "--by", "30,0",
                 "--duration", "1", "--set", "jm_joint2=-1e-7", "--out", str(tmp_path)])
    assert code == 2
    assert "jm_joint2 (rotor inertia) must be >= 0" in capsys.readouterr().err


def test_a_sweep_range(tmp_path):
    study = _study(tmp_path, "move", "")
    with pytest.raises(InputError, match=r"design 0 \(gear_joint1 = -10\) is not physical: "
                                         r"parameter gear_joint1 \(gear ratio\) must be > 0"):
        ps.sweep(study, {"gear_joint1": [-10.0, 10.0, 50.0]})


def test_a_value_typed_with_its_unit_reads_the_same_on_every_route():
    """with_parameters takes "500 g" as a study's [parameters] and --set do (it refused it:
    "must be a number in kg", user trial): the same SI value as the study route's conversion,
    as 0.5 in SI, and a unit of the wrong quantity is named."""
    from planar_sym.study.parameters import to_si

    arm = ps.load("serial_2dof")
    typed = arm.with_parameters(m_motor2="500 g", izz_link1="90.992 kg*mm^2")
    assert typed.parameters["m_motor2"] == 0.5 == to_si(arm, {"m_motor2": (500.0, "g")})[
        "m_motor2"]
    assert typed.parameters["izz_link1"] == pytest.approx(90.992e-6, rel=1e-15)
    assert np.array_equal(typed.p, arm.with_parameters(m_motor2=0.5,
                                                       izz_link1=90.992e-6).p)
    with pytest.raises(InputError, match=r"serial_2dof: parameter m_motor2: unknown mass unit "
                                         r"'mm'"):
        arm.with_parameters(m_motor2="500 mm")
    with pytest.raises(InputError, match=r"parameter m_motor2 .*must be > 0"):
        arm.with_parameters(m_motor2="-5 g")

"""Results as NPZ and as pandas DataFrames: ``Result`` (a study) and ``Simulation``
(``planar_sym.simulate``), and ``planar-sym run --npz``.

- NPZ round trip: every column back bit for bit (float64 bytes equal), in order, with the
  metadata; the CSV written beside it parses to the very same bits (17 significant digits);
- DataFrame: the columns (names with units, ``t_s`` a column) equal the Result's;
- a Simulation names its columns as the study CSVs do (a slider's in m, N), its tau columns
  by coordinate (a closed chain's: the actuated ones);
- without pandas: an ImportError that says ``pip install pandas``; ``import planar_sym``
  never imports pandas.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.dynamics.columns import METADATA_KEY, load_npz
from planar_sym.outputs.results import write
from planar_sym.study.result import coordinate_column

STUDY = "serial_rpr_tool_move"  # inverse dynamics of a robot with a slider: rad and m columns


@pytest.fixture(scope="module")
def result():
    return ps.run_study(STUDY, 51)


def same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def read_csv(path) -> dict[str, np.ndarray]:
    header, *rows = path.read_text().splitlines()
    table = np.array([[float(v) for v in row.split(",")] for row in rows])
    return {name: table[:, k] for k, name in enumerate(header.split(","))}


def test_npz_round_trip_is_bit_for_bit_and_matches_the_csv(result, tmp_path):
    paths = write(result, tmp_path, plot=False, npz=True)
    assert [p.name for p in paths] == [f"{STUDY}.csv", f"{STUDY}.npz"]
    columns, meta = load_npz(tmp_path / f"{STUDY}.npz")
    assert list(columns) == list(result.columns)
    assert all(same_bits(columns[k], v) for k, v in result.columns.items())
    csv = read_csv(tmp_path / f"{STUDY}.csv")
    assert list(csv) == list(columns)
    assert all(same_bits(csv[k], columns[k]) for k in csv)  # both are the same source arrays
    assert meta["study"] == STUDY and meta["robot"] == "serial_rpr" and meta["kind"] == "torques"
    raw = np.load(tmp_path / f"{STUDY}.npz")  # plain numpy reads it, no pickle
    assert same_bits(raw["q2_m"], result.columns["q2_m"]) and METADATA_KEY in raw.files


def test_dataframe_columns_are_the_results(result):
    df = result.to_dataframe()
    assert list(df.columns) == list(result.columns)
    assert "t_s" in df.columns and "q2_m" in df.columns and "tau2_n" in df.columns
    for k, v in result.columns.items():
        assert same_bits(df[k].to_numpy(), v), k
    assert df.attrs["study"] == STUDY and df.attrs["robot"] == "serial_rpr"
    assert df.to_csv(index=False, float_format="%.17g").splitlines()[0] == ",".join(
        result.columns)


def test_simulation_columns_npz_and_dataframe(tmp_path):
    robot = ps.load("serial_rpr")
    sim = ps.simulate(robot, robot.q_drawn, np.zeros(3), (0.0, 0.2), t_eval=np.linspace(0, 0.2, 21))
    cols = sim.columns()
    expected = ["t_s", *(coordinate_column(kind, k, robot.coordinate_units[k])
                         for kind in ("q", "qd", "tau") for k in range(3)),
                "kinetic_j", "potential_j", "energy_j"]
    assert list(cols) == expected  # the study CSVs' names: q2_m, qd2_m_s, tau2_n
    assert same_bits(cols["q2_m"], sim.q[:, 1]) and same_bits(cols["energy_j"], sim.energy_j)
    path = sim.save_npz(tmp_path / "free.npz")
    back, meta = load_npz(path)
    assert all(same_bits(back[k], v) for k, v in cols.items()) and list(back) == expected
    assert meta["robot"] == "serial_rpr" and meta["method"] == "dopri5"
    df = sim.to_dataframe()
    assert list(df.columns) == expected and same_bits(df["qd3_rad_s"].to_numpy(), sim.qd[:, 2])


def test_closed_chain_simulation_names_its_actuated_torques():
    robot = ps.load("five_bar_type1")  # A, B, E, D; actuated A and E
    sim = ps.simulate(robot, robot.q_drawn, np.zeros(4), (0.0, 0.05), torque=[0.01, -0.02],
                      t_eval=np.linspace(0, 0.05, 6))
    taus = [k for k in sim.columns() if k.startswith("tau")]
    assert taus == ["tau1_n_m", "tau3_n_m"]
    np.testing.assert_array_equal(sim.columns()["tau3_n_m"], -0.02)


def test_without_pandas_the_error_says_how_to_get_it(result, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas now raises ImportError
    with pytest.raises(ImportError, match="pip install pandas"):
        result.to_dataframe()


def test_import_planar_sym_does_not_import_pandas():
    code = ("import sys, planar_sym, planar_sym.outputs.results, planar_sym.outputs.export; "
            "r = planar_sym.load('serial_2dof'); "
            "assert 'pandas' not in sys.modules, 'pandas imported'")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_cli_run_npz(tmp_path, capsys):
    assert main(["run", STUDY, "--out", str(tmp_path), "--samples", "21", "--npz"]) == 0
    assert f"{STUDY}.npz" in capsys.readouterr().out
    columns, meta = load_npz(tmp_path / f"{STUDY}.npz")
    csv = read_csv(tmp_path / f"{STUDY}.csv")
    assert list(csv) == list(columns) and all(same_bits(csv[k], columns[k]) for k in csv)
    assert len(columns["t_s"]) == 21 and meta["study"] == STUDY

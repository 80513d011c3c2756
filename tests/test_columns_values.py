"""Named columns as NPZ and as a DataFrame (``planar_sym.dynamics.columns``), called directly:
the survivors of mutation testing (issue 30; tests/test_result_tables.py goes through Result and
Simulation).

- NPZ round trip: columns of awkward float64 values (-0.0, a subnormal, inf, a NaN with a
  payload, the largest float) and an int64 column come back bit for bit and in order, read by
  ``load_npz`` and by plain ``np.load`` without pickle; the metadata is one 0-d unicode entry
  holding ``json.dumps(metadata, sort_keys=True)`` (the same text whatever the insertion
  order); the file is exactly the path given (no suffix added), its folder created;
- ``load_npz`` of an NPZ without metadata gives ``{}``; of one holding a pickled object array,
  numpy's refusal (pickles are never loaded);
- refusals word for word: a folder as the path, a column named like the metadata entry
  (nothing written);
- DataFrame: the columns in order, equal bit for bit, ``attrs`` the metadata, the data a copy
  (writing to the source afterwards leaves it as it was); a list is a column too;
- without pandas: the ImportError's exact words.
"""

from __future__ import annotations

import struct
import sys

import numpy as np
import pytest

from planar_sym.dynamics.columns import METADATA_KEY, dataframe, load_npz, save_npz
from planar_sym.errors import InputError

META = {"study": "s1", "robot": "serial_2dof", "method": "dopri5"}  # not in sorted order


def _columns():
    nan_payload = struct.unpack("<d", struct.pack("<Q", 0x7FF8_0000_0000_0ABC))[0]
    return {"t_s": np.linspace(0.0, 0.3, 4),
            "q1_rad": np.array([-0.0, 5e-324, np.inf, nan_payload]),
            "tau1_n_m": np.array([np.finfo(float).max, -1.0 / 3.0, 1e-300, -np.inf]),
            "count": np.array([0, -7, 2**62, 3], dtype=np.int64)}


def same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def test_npz_round_trip_bit_for_bit(tmp_path):
    cols = _columns()
    path = tmp_path / "new" / "folder" / "run.data"  # no .npz: none is added
    assert save_npz(str(path), cols, META) == path
    assert sorted(p.name for p in path.parent.iterdir()) == ["run.data"]  # no temporary left
    back, meta = load_npz(path)
    assert list(back) == list(cols)
    assert all(same_bits(back[k], v) for k, v in cols.items())
    assert meta == META and list(meta) == ["method", "robot", "study"]
    with np.load(path, allow_pickle=False) as raw:
        assert raw.files == [*cols, METADATA_KEY]
        assert all(same_bits(raw[k], v) for k, v in cols.items())
        text = raw[METADATA_KEY]
        assert text.shape == () and text.dtype.kind == "U"
        assert str(text) == '{"method": "dopri5", "robot": "serial_2dof", "study": "s1"}'


def test_npz_of_no_metadata_and_of_a_pickle(tmp_path):
    plain = tmp_path / "plain.npz"
    np.savez(plain, t_s=np.arange(3.0))
    back, meta = load_npz(plain)
    assert list(back) == ["t_s"] and same_bits(back["t_s"], np.arange(3.0)) and meta == {}
    pickled = tmp_path / "pickled.npz"
    np.savez(pickled, t_s=np.array([{"a": 1}], dtype=object))
    with pytest.raises(ValueError, match="allow_pickle=False"):
        load_npz(pickled)


def test_npz_refusals_word_for_word(tmp_path):
    with pytest.raises(InputError) as exc:
        save_npz(tmp_path, _columns(), META)
    assert str(exc.value) == (f"NPZ file {tmp_path} is a folder; give a file name such as "
                              f"{tmp_path}/result.npz")
    cols = {"t_s": np.zeros(2), METADATA_KEY: np.zeros(2)}
    with pytest.raises(InputError) as exc:
        save_npz(tmp_path / "x.npz", cols, META)
    assert str(exc.value) == "a column may not be named '__metadata__' (the NPZ's metadata)"
    assert list(tmp_path.iterdir()) == []


def test_dataframe_is_a_copy_of_the_columns_with_the_metadata():
    pytest.importorskip("pandas")
    cols = _columns()
    df = dataframe(cols, META)
    assert list(df.columns) == list(cols)
    assert all(same_bits(df[k].to_numpy(), v) for k, v in cols.items())
    assert df.attrs == META
    before = cols["t_s"].copy()
    cols["t_s"][:] = -1.0  # the source changes afterwards: the frame does not
    assert same_bits(df["t_s"].to_numpy(), before)
    assert not np.shares_memory(df["t_s"].to_numpy(), cols["t_s"])
    listed = dataframe({"t_s": [0.0, 0.5], "x_m": [1.0, 2.0]}, {})
    assert same_bits(listed["x_m"].to_numpy(), np.array([1.0, 2.0])) and listed.attrs == {}


def test_without_pandas_the_exact_words(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # `import pandas` now raises ImportError
    with pytest.raises(ImportError) as exc:
        dataframe({"t_s": np.zeros(2)}, META)
    assert str(exc.value) == ("to_dataframe needs pandas, which is not installed: pip install "
                              "pandas (or write NPZ or CSV, which need nothing more)")
    assert exc.value.__cause__ is None and exc.value.__suppress_context__

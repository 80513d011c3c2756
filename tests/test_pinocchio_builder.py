"""The Pinocchio reference builder (benchmarks/baselines/pinocchio_model.py) is order-proof.

Pinocchio's ``crba`` assumes the joints were added depth-first (every subtree a contiguous
block of q/v indices). A description keeps its file's joint order where the tree allows, so a
file that writes its branches interleaved (A1, A2, A3, elbow1, elbow2, elbow3, B1 for a 3-RRR)
gave a model in which ``crba`` is silently wrong while ``rnea`` and ``aba`` stay right. These
tests write such files and show:

* built in the description's order (the old builder), ``crba`` disagrees with the mass matrix
  taken column by column from Pinocchio's own ``rnea`` (``M e_k = rnea(q, 0, e_k) - rnea(q, 0,
  0)``) by far more than rounding (measured: 0.52 relative for the 3-RRR, 0.031 for the
  slider-crank);
* built depth-first (the builder now), with its permutation between our coordinates and
  Pinocchio's indices, ``crba`` equals that matrix to 1e-12, and ``rnea`` and ``aba`` are
  those of the description-order model, permuted (they never depended on the order);
* the reordered robot's mass matrix and torques equal those of the built-in robot it was
  written from (the compiled code, coordinates matched by name) to 1e-10;
* ``pinocchio_model`` (callers that index Pinocchio as ours) refuses such a description.
"""

from __future__ import annotations

import re

import numpy as np
import pinocchio as pin
import pytest
from conftest import ROBOTS_DIR, random_states, rel_err
from pinocchio_model import pinocchio_model, pinocchio_tree

from planar_sym.model import description
from planar_sym.model.locate import load

#: built-in robot -> its joints in an interleaved order (branches alternate in the file)
INTERLEAVED = {
    "parallel_3rrr": ["A1", "A2", "A3", "elbow1", "elbow2", "elbow3", "B1", "B2", "B3"],
    "slider_crank": ["O", "slide", "A", "B"],  # the slider's branch before the rod's
    "serial_3dof": None,  # a chain has one branch: depth-first is its only order (control)
}


def reorder_joints(text: str, names: list[str]) -> str:
    """A description's text with its [[joints]] tables in the order ``names``."""
    chunks = re.split(r"(?m)^(?=\[)", text)
    joints = {re.search(r'(?m)^name = "([^"]+)"', c).group(1): c
              for c in chunks if c.startswith("[[joints]]")}
    first = next(i for i, c in enumerate(chunks) if c.startswith("[[joints]]"))
    rest = [c for c in chunks[first:] if not c.startswith("[[joints]]")]
    return "".join(chunks[:first] + [joints[n] for n in names] + rest)


def _written(tmp_path, robot: str):
    names = INTERLEAVED[robot]
    text = (ROBOTS_DIR / f"{robot}.toml").read_text()
    if names is not None:
        text = reorder_joints(text, names)
    path = tmp_path / f"{robot}.toml"
    path.write_text(text)
    return description.load(path)


def _rnea_mass_matrix(model, data, q) -> np.ndarray:
    """M from rnea alone, column by column (gravity and velocity terms subtracted)."""
    zero = np.zeros(model.nv)
    b = pin.rnea(model, data, q, zero, zero).copy()
    return np.column_stack([pin.rnea(model, data, q, zero, e) - b for e in np.eye(model.nv)])


def _crba(model, data, q) -> np.ndarray:
    m = pin.crba(model, data, q)
    return np.triu(m) + np.triu(m, 1).T


@pytest.mark.parametrize("robot", list(INTERLEAVED))
def test_crba_needs_depth_first_order(robot, tmp_path):
    desc = _written(tmp_path, robot)
    if INTERLEAVED[robot] is not None:
        assert [j.name for j in desc.tree_joints] == [n for n in INTERLEAVED[robot]
                                                      if n in desc.coordinates]  # as written
    old = pinocchio_tree(desc, order="description")
    new = pinocchio_tree(desc)
    assert old.identity  # the old builder: Pinocchio's indices are the description's
    assert new.identity == (INTERLEAVED[robot] is None)
    od, nd = old.model.createData(), new.model.createData()
    q, qd, tau = random_states(np.random.default_rng(2), 20, len(desc.coordinates))
    worst_old, worst_new, worst_rnea, worst_aba = 0.0, 0.0, 0.0, 0.0
    for qk, vk, tk in zip(q, qd, tau):
        m_rnea = _rnea_mass_matrix(old.model, od, qk)
        worst_old = max(worst_old, rel_err(_crba(old.model, od, qk)[None], m_rnea[None]))
        qp = new.to_pin(qk)
        m_new = new.matrix_from_pin(_crba(new.model, nd, qp))
        worst_new = max(worst_new, rel_err(m_new[None], m_rnea[None]))
        # rnea and aba never depended on the order: the same in both models, permuted
        rn = new.from_pin(pin.rnea(new.model, nd, qp, new.to_pin(vk), new.to_pin(tk)))
        worst_rnea = max(worst_rnea, rel_err(rn[None], pin.rnea(old.model, od, qk, vk, tk)[None]))
        ab = new.from_pin(pin.aba(new.model, nd, qp, new.to_pin(vk), new.to_pin(tk)))
        worst_aba = max(worst_aba, rel_err(ab[None], pin.aba(old.model, od, qk, vk, tk)[None]))
    print(f"{robot}: crba vs rnea-derived M, description order {worst_old:.1e}, "
          f"depth-first {worst_new:.1e} (order {new.order}); rnea {worst_rnea:.1e}, "
          f"aba {worst_aba:.1e}")
    if INTERLEAVED[robot] is not None:
        assert worst_old > 1e-3, "the old builder's crba should be wrong for interleaved joints"
    else:
        assert worst_old < 1e-12
    assert worst_new < 1e-12
    assert worst_rnea < 1e-12 and worst_aba < 1e-12


@pytest.mark.parametrize("robot", ["parallel_3rrr", "slider_crank"])
def test_interleaved_robot_is_the_built_in_one(robot, tmp_path):
    """The reordered file is the same robot: Pinocchio's depth-first model of it agrees with
    the built-in robot's compiled mass matrix and tree torques, coordinates matched by name."""
    desc = _written(tmp_path, robot)
    builtin = load(robot)
    idx = [builtin.coordinates.index(c) for c in desc.coordinates]  # ours -> the built-in's
    tree = pinocchio_tree(desc)
    data = tree.model.createData()
    q, qd, qdd = random_states(np.random.default_rng(4), 20, builtin.n)  # built-in order
    m_ref, tau_ref = [], []
    for qk, vk, ak in zip(q, qd, qdd):
        qp = tree.to_pin(qk[idx])
        m = tree.matrix_from_pin(_crba(tree.model, data, qp))
        inv = np.argsort(idx)
        m_ref.append(m[np.ix_(inv, inv)])
        t = tree.from_pin(pin.rnea(tree.model, data, qp, tree.to_pin(vk[idx]),
                                   tree.to_pin(ak[idx])))
        tau_ref.append(t[inv])
    assert rel_err(builtin.mass_matrix(q), np.array(m_ref)) < 1e-10
    assert rel_err(builtin.tree_inverse_dynamics(q, qd, qdd), np.array(tau_ref)) < 1e-10


def test_pinocchio_model_refuses_an_interleaved_description(tmp_path):
    desc = _written(tmp_path, "parallel_3rrr")
    with pytest.raises(ValueError, match="interleave"):
        pinocchio_model(desc)
    model, where = pinocchio_model(description.load("parallel_3rrr"))  # depth-first as written
    assert model.nv == 7 and set(where) == set(description.load("parallel_3rrr").bodies)

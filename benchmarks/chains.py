"""The robots of the growth benchmark: planar n-link pendulums and a three-loop linkage.

``chain_toml(n)`` is the textbook n-link pendulum: n equal uniform bars (0.3 m, 1 kg, izz = m L^2
/ 12) hanging from the origin, every joint a revolute with a motor, gravity -y. Written as a user
would write it (pose = "joints"), so nothing here is special-cased by planar-sym.
"""

from __future__ import annotations

from pathlib import Path

LENGTH_M, MASS_KG = 0.3, 1.0


def chain_toml(n: int) -> str:
    """The description of the n-link pendulum, as TOML text."""
    izz = MASS_KG * LENGTH_M**2 / 12
    out = [f'name = "chain_{n}"', f'title = "{n}-link pendulum (growth benchmark)"',
           'pose = "joints"', "gravity = [0.0, -9.81]", "",
           "[units]", 'length = "m"', 'mass = "kg"', 'inertia = "kg*m^2"', 'angle = "rad"',
           'acceleration = "m/s^2"', "", "[ground]", "points = { O = [0.0, 0.0] }", ""]
    for k in range(1, n + 1):
        out += ["[[bodies]]", f'name = "link{k}"', f"mass = {MASS_KG}", f"izz = {izz!r}",
                f"cg = [{LENGTH_M / 2}, 0.0]",
                f"points = {{ A = [0.0, 0.0], B = [{LENGTH_M}, 0.0] }}", ""]
    for k in range(1, n + 1):
        parent = "ground.O" if k == 1 else f"link{k - 1}.B"
        out += ["[[joints]]", f'name = "joint{k}"', 'type = "revolute"', f'parent = "{parent}"',
                f'child = "link{k}.A"', "actuated = true", f"angle = {-1.2 if k == 1 else 0.2}",
                ""]
    out += ["[task]", f'point = "link{n}.B"', ""]
    return "\n".join(out)


def write_chain(n: int, folder: Path) -> Path:
    """Write ``chain_<n>.toml`` into ``folder`` and return its path."""
    path = Path(folder) / f"chain_{n}.toml"
    path.write_text(chain_toml(n))
    return path

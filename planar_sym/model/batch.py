"""The generated functions' batch signature: what goes in and comes out, shared by the compiled
library (``library.BatchFunction``) and CasADi's evaluator (``evaluator.CasadiFunction``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class FunctionSpec:
    """One generated function as the manifest lists it: its C symbol, inputs (name, size) in
    call order (``p``, the parameter vector, is shared by all samples) and outputs (name, rows,
    cols, ``"scalar"``/``"vector"``/``"matrix"``)."""

    symbol: str
    inputs: tuple[tuple[str, int], ...]
    outputs: tuple[tuple[str, int, int, str], ...]


def shaped(spec: FunctionSpec, n: int, blocks: list[np.ndarray]) -> dict[str, np.ndarray]:
    """Per-sample output blocks (n, rows*cols), CasADi's column-major order, by output name:
    (n,) for a scalar, (n, rows) for a vector, (n, rows, cols) for a matrix."""
    out = {}
    for (name, rows, cols, kind), a in zip(spec.outputs, blocks):
        if kind == "scalar":
            out[name] = a[:, 0]
        elif kind == "vector":
            out[name] = a
        else:  # CasADi matrices are column-major
            out[name] = a.reshape(n, cols, rows).transpose(0, 2, 1)
    return out

"""Files written whole or not at all: temporary names beside the targets, renamed at the end."""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path


@contextlib.contextmanager
def atomic_files(targets: list[Path]) -> Iterator[list[Path]]:
    """Temporary paths beside ``targets``, renamed onto them only if the block succeeds.

    Each temporary file keeps its target's suffix, because writers such as matplotlib and
    Pillow pick the file format from it. On any exception every temporary file is removed and
    no target is touched, so a failed command never leaves a partial file.
    """
    temps: list[str] = []
    try:
        for target in targets:
            target.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix,
                                       dir=target.parent)
            os.close(fd)
            temps.append(tmp)
        yield [Path(t) for t in temps]
        for tmp, target in zip(temps, targets):
            os.chmod(tmp, 0o644)  # mkstemp makes 0600; results are meant to be shared
            os.replace(tmp, target)
    finally:
        for tmp in temps:
            if os.path.exists(tmp):
                os.unlink(tmp)

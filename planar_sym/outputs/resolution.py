"""One rule for a picture's resolution, whichever command asks for it (``draw``, ``atlas``,
``animate``): dots per inch from 10 to 600. The project's figures are at most 12 x 10 in, so no
picture needs more than 7200 x 6000 pixels; a larger request (``--dpi 100000``: 800,000 x
600,000 pixels, 1.9 TB) is refused before anything is allocated."""

from __future__ import annotations

import numpy as np

from ..errors import InputError

DPI_MIN, DPI_MAX = 10, 600


def check_dpi(dpi) -> int:
    """``dpi`` if it is an integer from DPI_MIN to DPI_MAX, else InputError."""
    if (isinstance(dpi, bool) or not isinstance(dpi, (int, np.integer))
            or not DPI_MIN <= dpi <= DPI_MAX):
        raise InputError(f"--dpi must be an integer from {DPI_MIN} to {DPI_MAX} (got {dpi})")
    return int(dpi)

"""Per-scenario status codes shared by every study (CF ``flag_values`` / ``flag_meanings``).

A scenario that fails never stops a study and never hides as a number: its outputs are NaN and
its ``status`` says why.
"""
from __future__ import annotations

import numpy as np

#: code -> meaning; codes are stable (stored in files), append only.
FLAGS = {
    0: "ok",
    1: "invalid_geometry",
    2: "monotone_no_hump",
    3: "snap_through",
    4: "never_locked",
    5: "jammed",
    6: "not_converged",
    7: "above_allowable",
    8: "not_engaged",
    9: "roll_over",
    10: "pop_out_risk",
    11: "not_self_locking",
    12: "overrunning",
    13: "truncated",
}
CODE = {meaning: code for code, meaning in FLAGS.items()}
DTYPE = np.int8


def attrs(description: str = "") -> dict:
    """CF attributes of a ``status`` variable."""
    out = {
        "long_name": "scenario status",
        "units": "1",
        "flag_values": np.array(sorted(FLAGS), dtype=DTYPE),
        "flag_meanings": " ".join(FLAGS[k] for k in sorted(FLAGS)),
    }
    if description:
        out["comment"] = description
    return out


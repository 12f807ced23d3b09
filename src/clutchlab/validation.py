"""Validation rows: a published number, what clutchlab computes for it, and the verdict.

Each seed contributes a Dataset with one ``row`` per reproduced number; the report writes the
union as ``validation.csv`` and as a table page.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

__all__ = ["Row", "to_dataset", "to_csv"]

COLUMNS = [
    "seed",
    "quantity",
    "source",
    "published",
    "computed",
    "units",
    "rel_error",
    "tolerance",
    "passed",
    "note",
]


@dataclass(frozen=True)
class Row:
    seed: str
    quantity: str
    source: str
    published: float
    computed: float
    units: str
    tolerance: float  # relative
    note: str = ""

    @property
    def rel_error(self) -> float:
        """Relative error; absolute where the published value is 0 (e.g. "capacity at idle")."""
        if self.published == 0:
            return abs(self.computed)
        return abs(self.computed - self.published) / abs(self.published)

    @property
    def passed(self) -> bool:
        return bool(self.rel_error <= self.tolerance)

    @classmethod
    def against(cls, published, computed, tolerance, note="", quantity=None) -> Row:
        """The row comparing ``computed`` with a number of :mod:`clutchlab.published`.

        Parameters
        ----------
        published : clutchlab.published.Published
            The paper's number: gives the row's seed, source, published value and units.
        computed : float
            clutchlab's value [the published number's units].
        tolerance : float
            Relative tolerance [1] (absolute where the published value is 0).
        note : str
            Assumptions and errata.
        quantity : str or None
            The row's name where it differs from the published number's (the same number
            compared with two readings).
        """
        return cls(
            published.paper,
            quantity or published.quantity,
            published.source,
            published.value,
            float(computed),
            published.units,
            tolerance,
            note,
        )


def to_dataset(rows: list[Row], title: str) -> xr.Dataset:
    """Rows -> Dataset on dimension ``row`` with units and long_name everywhere."""

    def text(name, long_name):
        return (
            "row",
            np.array([getattr(r, name) for r in rows], dtype=object),
            {"long_name": long_name, "units": ""},
        )

    mixed = "mixed: see variable 'units' (row-wise)"
    ds = xr.Dataset(
        {
            "seed": text("seed", "seed paper"),
            "quantity": text("quantity", "reproduced quantity"),
            "source": text("source", "where the published value is printed"),
            "published": (
                "row",
                [r.published for r in rows],
                {"long_name": "published value", "units": mixed},
            ),
            "computed": (
                "row",
                [r.computed for r in rows],
                {"long_name": "clutchlab value", "units": mixed},
            ),
            "units": text("units", "units of published and computed (row-wise)"),
            "rel_error": (
                "row",
                [r.rel_error for r in rows],
                {"long_name": "relative error", "units": "1"},
            ),
            "tolerance": (
                "row",
                [r.tolerance for r in rows],
                {"long_name": "relative tolerance", "units": "1"},
            ),
            "passed": (
                "row",
                np.array([r.passed for r in rows], dtype=np.int8),
                {"long_name": "within tolerance (1) or not (0)", "units": "1"},
            ),
            "note": text("note", "assumptions and errata"),
        },
        coords={"row": ("row", np.arange(len(rows)), {"long_name": "row index", "units": "1"})},
        attrs={"title": title},
    )
    return ds


def to_csv(datasets: list[xr.Dataset], path) -> None:
    """Write the rows of several validation Datasets as one CSV table (published and computed in
    the units engineers read: a stress stored in Pa in MPa, :func:`clutchlab.display.reported`)."""
    import csv

    from .display import reported

    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(COLUMNS)
        for ds in datasets:
            for i in range(ds.sizes["row"]):
                vals = []
                (pub, com), unit = reported(
                    [ds["published"].values[i], ds["computed"].values[i]],
                    str(ds["units"].values[i]),
                    typeset=False,
                )
                shown = {"published": pub, "computed": com, "units": unit}
                for c in COLUMNS:
                    v = shown.get(c, ds[c].values[i])
                    if c in ("published", "computed"):
                        v = f"{float(v):.6g}"
                    elif c in ("rel_error", "tolerance"):
                        v = f"{float(v):.3e}"
                    elif c == "passed":
                        v = "yes" if int(v) else "no"
                    vals.append(v)
                w.writerow(vals)

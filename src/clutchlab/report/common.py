"""Report pages and helpers shared by every study: seed selection, title page, validation table."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np

from .. import display
from .. import status as st

A4_LANDSCAPE = (11.69, 8.27)

# an objective's sense on an axis ("(min)" beside a unit reads as minutes)
SENSE_WORDS = {"min": "minimised", "max": "maximised"}

FRONTS_NAMED = 8  # fronts (one per operating condition) a legend names, each in a colour of its own


def front_colour(j: int):
    """The colour of the ``j``-th operating condition's front, the same on every page: one of
    its own for each of the first :data:`FRONTS_NAMED` (not blue: the feasible designs'), one
    for all the others."""
    return plt.cm.tab10(min(j + 1, FRONTS_NAMED + 1))


def with_curves(ds):
    """A sampled result that stores its per-scenario curves for a subset of scenarios (dimension
    ``curve_run``) as the Dataset of that subset on ``run``, curves included;
    any other result unchanged. Pages that draw curves pick their designs from it."""
    if "curve_run" not in ds.dims:
        return ds
    curves = [n for n, v in ds.data_vars.items() if "curve_run" in v.dims]
    position = {int(r): i for i, r in enumerate(ds["run"].values)}
    base = ds.drop_vars(curves + ["curve_run"]).isel(
        run=[position[int(r)] for r in ds["curve_run"].values]
    )
    return base.assign(
        {
            n: (
                tuple("run" if d == "curve_run" else d for d in ds[n].dims),
                ds[n].values,
                ds[n].attrs,
            )
            for n in curves
        }
    )


def seed_view(ds, seed, keep=()):
    """The scenario(s) nearest the ``seed`` design (parameter -> value): factorial dims other
    than ``keep`` selected at the seed value; a sampled design gives the run nearest in normalised
    distance."""
    if "run" in ds.dims:
        dist = np.zeros(ds.sizes["run"])
        options = ds.attrs.get("option_factors", "").split()
        for name in ds.attrs.get("factors", "").split():
            v = ds[name].values
            if (
                name in options
            ):  # an option drawn per scenario: its first listed choice, as the traces
                dist += np.where(v == 0, 0.0, 1e6)
                continue
            dist += ((v - seed[name]) / (np.ptp(v) or 1.0)) ** 2
        return ds.isel(run=int(np.argmin(dist)))
    sel = {d: seed[d] for d in ds.dims if d in seed and d not in keep}
    return ds.sel(sel, method="nearest") if sel else ds


def fixed_text(sub, dims):
    """ "name = value unit" for the scalar coordinates ``dims`` of a selection, in the units
    engineers read (:mod:`clutchlab.display`)."""
    out = []
    for d in dims:
        if d in sub.coords and sub[d].ndim == 0 and d == "noise":
            # which draw: its index, named as one, and its deviations (friction_coefficient +20 %)
            draw = noise_text(sub)
            out.append(f"noise draw {int(sub[d])}" + (f" ({draw})" if draw else ""))
        elif d in sub.coords and sub[d].ndim == 0:
            out.append(f"{d} = {display.text(float(sub[d]), display.unit_of(sub, d))}")
    return ", ".join(out)


def constraints(ds) -> list[tuple[str, str, float]]:
    """(output, "min" or "max", limit [SI]) of each constraint of a study result (its
    ``constraint`` coordinate's ``limits``: "reserve_factor:min:1.2 ..."); none without one."""
    if "constraint" not in ds.coords:
        return []
    items = str(ds["constraint"].attrs.get("limits", "")).split()
    return [(output, op, float(value)) for output, op, value in (i.split(":") for i in items)]


def constraint_limit(ds, output) -> float | None:
    """The limit of the study's constraint on ``output`` [SI], or None without one."""
    return next((limit for name, _, limit in constraints(ds) if name == output), None)


def noise_text(sub) -> str:
    """The noise draw of a selection as its deviations: "friction_coefficient +20 %" (relative)
    or "ambient_temperature 55 °C" (absolute); empty where it has none."""
    parts = []
    for name in sub.data_vars:
        if not name.endswith("_noise") or sub[name].ndim:
            continue
        v, param = float(sub[name]), name[: -len("_noise")]
        if sub[name].attrs.get("relative"):
            parts.append(f"{param} {100 * v:+.3g} %")
        else:
            parts.append(f"{param} {display.text(v, display.unit_of(sub, name))}")
    return ", ".join(parts)


def shown(ds) -> dict | None:
    """The factor values (SI) of the design the run's pages show (:mod:`clutchlab.traces`), for
    slicing a grid at it; None where the run shows none."""
    from ..explore import flat
    from ..traces import _factors, shown_design

    i = int(ds.attrs["shown_index"]) if "shown_index" in ds.attrs else shown_design(ds)[0]
    if i is None or i < 0:
        return None
    if i >= ds["status"].size:
        raise ValueError(
            f"the shown design's index {i} is outside this Dataset of {ds['status'].size} "
            "scenarios (a curve subset: take the shown design of the whole run)"
        )
    return {f: float(flat(ds, f)[i]) for f in _factors(ds)}


def value_at_shown(ds, name, default):
    """A parameter's value (SI) at the design the run shows: a fixed value, its factor value, or
    ``default`` (the study's) where the run has neither."""
    from ..explore import flat

    if name in ds and ds[name].ndim == 0 and "flag_meanings" not in ds[name].attrs:
        return float(ds[name])
    at = shown(ds)
    if at is not None and name in at:
        return at[name]
    if name in ds.coords and ds[name].size:
        return float(flat(ds, name)[0])
    return default


def shown_name(ds) -> str:
    """How a page names the design it shows: the source paper's design, or the run's best design
    (why it is the one) with its factor values; the status where it is not ok."""
    if "shown_index" not in ds.attrs or int(ds.attrs["shown_index"]) < 0:
        return "no design of this run to show: " + ds.attrs.get("shown_reason", "no traces")
    if ds.attrs.get("shown_reason", "").startswith("the run's best robust"):
        what = "the run's best robust design at its binding condition"
    elif ds.attrs.get("shown_reason", "").startswith("the run's best"):
        what = "the run's best design"
    else:
        what = "the run's design nearest the ideal point (no feasible design)"
    if int(ds.attrs.get("shown_is_paper", 0)):
        what += ", the source paper's design"
    status = ds.attrs.get("shown_status", "ok")
    return f"{what}: {ds.attrs['shown_design']}" + (f" (status {status})" if status != "ok" else "")


def page_ranges(numbers, stems) -> str:
    """ "pages 6-11, 27" of the stems' PDF pages (``numbers``: stem -> (first, last))."""
    pages = sorted({k for s in stems for k in range(numbers[s][0], numbers[s][1] + 1)})
    runs, start = [], None
    for k, nxt in zip(pages, pages[1:] + [None], strict=True):
        start = k if start is None else start
        if nxt != k + 1:
            runs.append(f"{start}" if start == k else f"{start}-{k}")
            start = None
    return ("pages " if len(pages) > 1 else "page ") + ", ".join(runs)


EXPLORER_LINE = "interactive explorer (open in a browser): "


def study_summary(name, ds, robust=None) -> dict:
    """What the summary page says of one study, from its result (the slow part: its best design),
    as plain data (the pages job of a study writes it beside its PDF part): its title line, its
    scenarios and design, its model, its status counts and its answers' lines (a robust study's
    robust front and best robust design first: ``robust``, its robust answers)."""
    from . import status_counts
    from .answers import best_text, edge_notes, life_text

    dims = " x ".join(f"{d} ({ds.sizes[d]})" for d in ds["status"].dims)
    if list(ds["status"].dims) == ["run"]:  # a sampled design: its factors
        dims = ", ".join(ds.attrs.get("factors", "").split()) or "run"
    n = int(np.prod([ds.sizes[d] for d in ds["status"].dims])) if ds["status"].dims else 1
    answers = []
    if robust is not None:
        from .robust import summary_lines

        answers += summary_lines(robust)
    if "pareto_rank" in ds:
        if robust is None:  # (a robust study's per-scenario fronts are its answers page's)
            answers.append("best compromise: " + best_text(ds))
        if life_text(ds):  # its reserve at the end of wear, lining life, engagements per hour
            answers.append("over its life: " + life_text(ds))
        if not ds.attrs.get("shown_reason", "the run's best").startswith("the run's best"):
            answers.append("trace pages: " + shown_name(ds))
        notes = edge_notes(ds, short=True)
        if notes:
            answers.append("at the edge of its range (widen it): " + "; ".join(notes))
    return {
        "name": name,
        "title": f"Study '{name}': {ds.attrs.get('title', '')}",
        "run": f"{n} scenarios, design {ds.attrs.get('design')} over {dims}",
        "model": str(ds.attrs.get("model", "")),
        "status": "status: " + ", ".join(f"{k} {v}" for k, v in status_counts(ds).items()),
        "answers": answers,
    }


def _study_lines(summary, numbers, job_seconds, model=True, explorer=None) -> list[str]:
    """The summary page's lines of one study (:func:`study_summary`; long lines are wrapped by the
    caller): with its jobs' time (``job_seconds``), its pages (``numbers``) and ``explorer``, the
    file name of its explorer beside the PDF, linked."""
    name = summary["name"]
    jobs = (
        f"; {job_seconds[name][0]} jobs, {job_seconds[name][1]:.1f} s of job time"
        if job_seconds and name in job_seconds
        else ""
    )
    lines = [
        summary["title"],
        summary["run"] + jobs,
        (f"model: {summary['model']}; " if model else "") + summary["status"],
        *summary["answers"],
    ]
    stems = [s for s in numbers if s.startswith(f"{name}_")]
    if stems:
        lines.append(
            page_ranges(numbers, stems) + ": " + ", ".join(s[len(name) + 1 :] for s in stems)
        )
    if explorer:
        lines.append(EXPLORER_LINE + explorer)
    return lines


_SUMMARY_FONTS = ((9.5, True), (9.0, True), (8.5, True), (8.0, True), (8.0, False))
_SUMMARY_TOP, _SUMMARY_BOTTOM = 0.96, 0.065  # the summary's text band [fraction of an A4 page]
_SUMMARY_FOOT = (
    "Units: SI inside every result file (units attribute on each variable); pages and CSV "
    "files in the units engineers read (mm, deg, MPa, kN, N·m, rpm, °C, ms, kJ)."
)


def summary_layout(title, summaries, validations, numbers=None, job_seconds=None, explorers=None):
    """How the summary's lines fit A4 pages: (font size [pt], the title's lines, the blocks of
    lines of each page). The largest font (9.5 down to 8 pt, the model lines left out last) whose
    lines fit the first page; where none does, 8 pt without the model lines over as many pages as
    the lines need (no study's block split where it fits a page). Arguments as :func:`title_page`."""
    numbers, explorers = numbers or {}, explorers or {}
    head = textwrap.wrap(title, 70)
    tail = _validation_block(validations, numbers)
    first = _SUMMARY_TOP - len(head) * 0.045 - 0.05 - _SUMMARY_BOTTOM  # below the version line
    for size, model in _SUMMARY_FONTS:
        chars = int(0.9 * A4_LANDSCAPE[0] * 72 / (0.53 * size))
        blocks = [
            _study_lines(s, numbers, job_seconds, model, explorers.get(s["name"]))
            for s in summaries
        ]
        wrapped = [
            [w for line in b for w in textwrap.wrap(line, chars, subsequent_indent="    ")]
            for b in blocks + tail
        ]
        if _blocks_height(wrapped, size) <= first:
            return size, head, [wrapped]
    later = _SUMMARY_TOP - _SUMMARY_BOTTOM - 0.04  # below "summary (continued)"
    return size, head, _paginate(wrapped, _summary_step(size), first, later)


def _validation_block(validations, numbers) -> list[list[str]]:
    """The summary's validation verdict (a block of one line), if any study reproduces numbers."""
    if not validations:
        return []
    n = sum(v.sizes["row"] for v in validations)
    ok = sum(int(v["passed"].sum()) for v in validations)
    where = page_ranges(numbers, ["validation_table"]) if "validation_table" in numbers else ""
    return [
        [
            f"Validation: {ok} of {n} reproduced numbers of the source papers within tolerance "
            f"(table on {where}; validation.csv)."
        ]
    ]


def _paginate(blocks, step, first, later) -> list:
    """The blocks of lines over pages of ``first`` (the first) and ``later`` height (fractions of
    a page; ``step`` a line's): a block moves to the next page where it fits a page, else it is
    split where the page ends."""
    pages, used, room = [[]], 0.0, first
    for block in blocks:
        lines = list(block)
        while lines:
            fit = int((room - used) / step)
            if fit >= len(lines) or (fit > 0 and len(lines) * step > later):
                pages[-1].append(lines[:fit])
                used += (min(fit, len(lines)) + 0.6) * step
                lines = lines[fit:]
            if lines:
                pages.append([])
                used, room = 0.0, later
    return pages


def _blocks_height(blocks, size) -> float:
    """The height of blocks of summary lines at ``size`` pt (a gap of 0.6 line after each), as a
    fraction of an A4 page."""
    return (sum(len(b) for b in blocks) + 0.6 * len(blocks)) * _summary_step(size)


def _summary_step(size) -> float:
    """A summary line's height at ``size`` pt, as a fraction of an A4 page."""
    return 1.3 * size / (A4_LANDSCAPE[1] * 72)


def title_page(
    title,
    version,
    summaries,
    validations,
    numbers=None,
    job_seconds=None,
    explorers=None,
    page=None,
):
    """The summary page: per study (``summaries``: its :func:`study_summary`, in report order) what
    was run (and how long its jobs took: ``job_seconds``, study -> (jobs, seconds)), its status
    counts, its best compromise design (values in the units engineers read), the factors it sits
    at the edge of, the pages that show it (``numbers``: page stem -> (first, last) page of the
    PDF) and its interactive explorer (``explorers``: study -> file name beside the PDF, a link in
    the PDF); the validation verdict and the pages of its table. Text 8 pt or more, inside the
    page. Where the lines need more than one A4 page (:func:`summary_layout`): ``page`` None, one
    figure as tall as they need (the PNG); ``page`` k, its A4 page k (the PDF)."""
    size, head, pages = summary_layout(
        title, summaries, validations, numbers, job_seconds, explorers
    )
    if page is not None or len(pages) == 1:
        k = page or 0
        return _summary_figure(title, version, head, pages[k], size, A4_LANDSCAPE[1], k > 0)
    blocks = [b for p in pages for b in p]
    text = _blocks_height(blocks, size)
    height = A4_LANDSCAPE[1] * max(1.0, (text + 0.3) / (_SUMMARY_TOP - _SUMMARY_BOTTOM))
    return _summary_figure(title, version, head, blocks, size, height, False)


def _summary_figure(title, version, head, blocks, size, height, continued):
    """One figure of the summary (``height`` [in]: A4, or taller for the whole of it)."""
    fig = plt.figure(figsize=(A4_LANDSCAPE[0], height))
    scale = A4_LANDSCAPE[1] / height  # (positions below are in A4 fractions from the top)

    def at(y):
        return 1.0 - (1.0 - y) * scale

    if continued:
        fig.text(0.05, at(_SUMMARY_TOP), f"{title}: summary (continued)", fontsize=11, va="top")
        y = _SUMMARY_TOP - 0.04
    else:
        # the title is the user's text: drawn as written ("$" is not mathtext), wrapped to the page
        fig.text(
            0.05, at(_SUMMARY_TOP), "\n".join(head), fontsize=20, weight="bold", va="top",
            parse_math=False,
        )  # fmt: skip
        top = _SUMMARY_TOP - len(head) * 0.045
        fig.text(0.05, at(top - 0.005), f"clutchlab {version}", fontsize=11, color="0.3", va="top")
        y = top - 0.05
    step = _summary_step(size)
    for block in blocks:
        for k, line in enumerate(block):
            url = line[len(EXPLORER_LINE) :] if line.startswith(EXPLORER_LINE) else None
            bold = k == 0 and line.startswith(("Study '", "Validation: "))  # (not a block's rest)
            fig.text(
                0.05, at(y), line, fontsize=size, weight="bold" if bold else None, va="top",
                url=url, color="tab:blue" if url else None,
            )  # fmt: skip
            y -= step
        y -= 0.6 * step
    fig.text(0.05, 0.025 * scale, _SUMMARY_FOOT, fontsize=8, color="0.4")
    return fig


# ---- tables ----------------------------------------------------------------------------------
TABLE_FONT = 8.0  # pt: the smallest text of any page
_LINE_IN = 1.3 * TABLE_FONT / 72  # a text line of a cell [in]
_PAD_IN = 0.07  # a cell's padding above and below [in]
_TOP_IN, _BOTTOM_IN = 0.75, 0.3  # the title band and the bottom margin of a page [in]


class Table:
    """A table of text cells at 8 pt, each cell wrapped to its column's width: one tall figure
    (the PNG) and as many A4 landscape pages as its rows need (the PDF), every row on a page and
    the header on each. ``verdict``: the column whose "NO" cells are red."""

    def __init__(self, title, cols, rows, widths, verdict="pass"):
        self.title, self.cols, self.widths, self.verdict = title, cols, widths, verdict
        chars = [
            max(4, int(w * 0.98 * A4_LANDSCAPE[0] * 72 / (0.56 * TABLE_FONT)) - 2) for w in widths
        ]
        self.rows = [
            [
                "\n".join(textwrap.wrap(str(c), n, break_long_words=True)) or ""
                for c, n in zip(r, chars, strict=True)
            ]
            for r in rows
        ]
        self.header = ["\n".join(textwrap.wrap(c, n)) for c, n in zip(cols, chars, strict=True)]
        per_page = A4_LANDSCAPE[1] - _TOP_IN - _BOTTOM_IN - self._height(self.header)
        self.chunks, chunk, used = [], [], 0.0
        for r in self.rows:
            h = self._height(r)
            if chunk and used + h > per_page:
                self.chunks.append(chunk)
                chunk, used = [], 0.0
            chunk.append(r)
            used += h
        self.chunks.append(chunk)

    @staticmethod
    def _height(row) -> float:
        return max(c.count("\n") + 1 for c in row) * _LINE_IN + 2 * _PAD_IN

    @property
    def n_pages(self) -> int:
        return len(self.chunks)

    def figure(self):
        """The whole table on one figure as tall as its rows need (the PNG)."""
        body = self._height(self.header) + sum(self._height(r) for r in self.rows)
        return self._draw(self.title, self.rows, max(A4_LANDSCAPE[1], _TOP_IN + _BOTTOM_IN + body))

    def pages(self) -> list:
        """The table on A4 landscape pages (the PDF)."""
        n = self.n_pages
        return [
            self._draw(f"{self.title} (page {k + 1} of {n})", chunk, None)
            for k, chunk in enumerate(self.chunks)
        ]

    def _draw(self, title, rows, height):
        height = height or A4_LANDSCAPE[1]
        fig = plt.figure(figsize=(A4_LANDSCAPE[0], height))
        fig.text(0.01, 1.0 - 0.3 / height, title, fontsize=12, weight="bold", va="top")
        body = self._height(self.header) + sum(self._height(r) for r in rows)
        top = 1.0 - _TOP_IN / height
        ax = fig.add_axes([0.01, top - body / height, 0.98, body / height])
        ax.axis("off")
        if not rows:
            return fig
        table = ax.table(
            cellText=rows, colLabels=self.header, cellLoc="left", colWidths=self.widths,
            bbox=(0.0, 0.0, 1.0, 1.0),
        )  # fmt: skip
        table.auto_set_font_size(False)
        table.set_fontsize(TABLE_FONT)
        verdict = self.cols.index(self.verdict) if self.verdict in self.cols else -1
        for (r, c), cell in table.get_celld().items():
            cell.set_height(self._height(self.header if r == 0 else rows[r - 1]) / body)
            cell.PAD = 0.06 / (self.widths[c] * A4_LANDSCAPE[0])  # 0.06 in each side
            cell.get_text().set_va("center")
            if r > 0 and c == verdict and cell.get_text().get_text() == "NO":
                cell.set_facecolor("#f4c7c3")
        return fig


def validation_table(validations) -> Table:
    """The reproduced numbers of the source papers, every row (paginated in the PDF)."""
    rows = []
    for v in validations:
        for i in range(v.sizes["row"]):
            (pub, com), unit = display.reported(
                [v["published"].values[i], v["computed"].values[i]], str(v["units"].values[i])
            )
            rows.append(
                [
                    str(v["seed"].values[i]),
                    str(v["quantity"].values[i]),
                    str(v["source"].values[i]),
                    f"{float(pub):.5g}",
                    f"{float(com):.5g}",
                    unit,
                    f"{float(v['rel_error'].values[i]):.2e}",
                    f"{float(v['tolerance'].values[i]):.2g}",
                    "yes" if int(v["passed"].values[i]) else "NO",
                    str(v["note"].values[i]),
                ]
            )
    cols = [
        "paper",
        "quantity",
        "source",
        "published",
        "computed",
        "units",
        "rel. error",
        "tol.",
        "pass",
        "note",
    ]
    return Table(
        "Validation against the source papers",
        cols,
        rows,
        [0.04, 0.23, 0.1, 0.07, 0.07, 0.055, 0.065, 0.05, 0.04, 0.28],
    )


def _error_unit(ds, i) -> str:
    """ "rel." for a relative error of hard case ``i``, else its unit (an older file: none)."""
    if ds["error_kind"].values[i] == "relative":
        return "rel."
    return str(ds["error_unit"].values[i]) if "error_unit" in ds else ""


def hard_case_table(ds) -> Table:
    """The hard cases (:mod:`clutchlab.hardcases`) as a table (paginated in the PDF)."""
    rows = []
    for i in range(ds.sizes["case"]):
        err = float(ds["error"].values[i])
        rows.append(
            [
                str(ds["study"].values[i]),
                str(ds["name"].values[i]),
                str(ds["right_answer"].values[i]),
                str(ds["source"].values[i]),
                str(ds["computed"].values[i]),
                "status" if np.isnan(err) else f"{err:.1e} " + _error_unit(ds, i),
                "" if np.isnan(err) else f"{float(ds['tolerance'].values[i]):.2g}",
                "yes" if int(ds["passed"].values[i]) else "NO",
                str(ds["off_the_shelf"].values[i]),
            ]
        )
    cols = [
        "study",
        "case",
        "right answer",
        "source",
        "clutchlab (this run)",
        "error",
        "tol.",
        "pass",
        "off-the-shelf solver",
    ]
    n_pass = int(ds["passed"].values.sum())
    return Table(
        f"Hard cases: {n_pass} of {ds.sizes['case']} pass (computed in this run; hard_cases.csv)",
        cols,
        rows,
        [
            0.08,
            0.13,
            0.15,
            0.11,
            0.16,
            0.07,
            0.05,
            0.035,
            0.17,
        ],  # (a study name, a tolerance on one line)
    )


def contour_level(ax, x, y, z, level, **kw):
    """The contour of ``z`` at ``level`` where the grid can carry one (at least 2 × 2 points) and the
    level is crossed; None otherwise (a design may hold a single value of a mapped factor)."""
    z = np.asarray(z, float)
    if z.ndim != 2 or min(z.shape) < 2 or not (np.nanmin(z) < level < np.nanmax(z)):
        return None
    return ax.contour(x, y, z, levels=[level], **kw)


def label_contour(ax, cs, text, height):
    """Label the contour ``cs`` (of one level) with ``text`` [8 pt] once, where it passes
    ``height`` (0 bottom to 1 top of the axes): two contours close together are labelled at two
    heights, not side by side over each other."""
    points = np.concatenate([p.vertices for p in cs.get_paths() if len(p.vertices)] or [[]])
    if not len(points):
        return
    y0, y1 = ax.get_ylim()
    at = points[np.argmin(np.abs(points[:, 1] - (y0 + height * (y1 - y0))))]
    ax.clabel(cs, fmt=text, fontsize=8, manual=[tuple(at)])


# above this many designs a sampled map shows binned shares instead of one marker per design
SCATTER_MAX = 4000


def wrap_name(name, width) -> str:
    """A name wrapped at its underscores or spaces (never inside a word): ``sheet_\nthickness``."""
    import re

    parts = [p for p in re.split(r"(?<=[_ ])", name) if p]
    lines, line = [], ""
    for p in parts:
        if line and len(line) + len(p.rstrip()) > width:
            lines.append(line.rstrip())
            line = ""
        line += p
    return "\n".join(lines + [line.rstrip()])


def column_chars(ax, share, fontsize, em=0.62) -> int:
    """Characters of text at ``fontsize`` [pt] (``em``: a character's mean width in ems) that fit
    a table column taking ``share`` of the width of ``ax``."""
    axes_w = ax.get_position().width * ax.figure.get_figwidth()
    return int(share * axes_w * 72.0 / (em * fontsize))


def shortened_to(ax, text, share, fontsize) -> str:
    """``text`` shortened at word ends (``textwrap.shorten``) to what fits, measured, in a table
    column taking ``share`` of the width of ``ax`` at ``fontsize`` [pt] within the cell's
    padding; each line on its own."""
    from matplotlib.font_manager import FontProperties

    renderer = ax.figure.canvas.get_renderer()
    room = 0.8 * share * ax.get_position().width * ax.figure.get_figwidth() * ax.figure.dpi
    font = FontProperties(size=fontsize)

    def width(line):
        return renderer.get_text_width_height_descent(line, font, ismath=False)[0]

    out = []
    for line in text.split("\n"):
        n = len(line)
        while n > 10 and width(line) > room:
            n -= 2
            line = textwrap.shorten(line, n)
        out.append(line)
    return "\n".join(out)


def _table_frame(ax, header, widths, fontsize):
    """A table's frame on ``ax``: (the axes' height [in], relative column widths, the column
    names wrapped to their columns, a line's height [in], the header row's height [in])."""
    axes_h = ax.get_position().height * ax.figure.get_figheight()
    widths = np.ones(len(header)) if widths is None else np.asarray(widths, dtype=float)
    widths = widths / widths.sum()
    chars = [max(6, column_chars(ax, w, fontsize)) for w in widths]
    labels = [wrap_name(h, n) for h, n in zip(header, chars, strict=True)]
    line_in = 1.2 * fontsize / 72.0
    head_in = (max(label.count("\n") for label in labels) + 1.6) * line_in
    return axes_h, widths, labels, line_in, head_in


def table_rows_fitting(ax, header, widths=None, fontsize=8.0) -> int:
    """How many rows of one line :func:`fitted_table` draws on ``ax`` at full height (more
    would be shrunk until their text overprints)."""
    axes_h, _, _, line_in, head_in = _table_frame(ax, header, widths, fontsize)
    return max(int((axes_h - head_in) / (1.6 * line_in)), 0)


def fitted_table(ax, header, cells, widths=None, fontsize=8.0):
    """A table across the width of ``ax``, from its top: the column names wrapped to their
    column (:func:`wrap_name`; ``widths`` relative, default equal), the header row as tall as
    the most wrapped one, each row its cells' lines of text and 0.6 more, or its share of what
    is left of the axes — a short table is not stretched over its axes, a long one never runs
    past them. Returns the matplotlib table."""
    axes_h, widths, labels, line_in, head_in = _table_frame(ax, header, widths, fontsize)
    # each row as tall as its most wrapped cell, all shrunk alike where they would run past the axes
    rows_in = np.array([(max(str(c).count("\n") for c in row) + 1.6) * line_in for row in cells])
    if rows_in.sum() > axes_h - head_in:
        rows_in *= max(axes_h - head_in, 0.0) / rows_in.sum()
    height = min(1.0, (head_in + rows_in.sum()) / axes_h)
    table = ax.table(
        cellText=cells,
        colLabels=labels,
        colWidths=list(widths),
        cellLoc="center",
        bbox=(0.0, 1.0 - height, 1.0, height),
    )
    table.auto_set_font_size(False)
    table.set_fontsize(fontsize)
    for (r, _c), cell in table.get_celld().items():
        cell.set_height((head_in if r == 0 else rows_in[r - 1]) / axes_h)
    return table


def _edges(v, bins):
    """Bin edges for a map axis: midway between the values of a discrete factor (at most ``bins``
    distinct values, e.g. a count), else ``bins`` equal bins over the values' range."""
    u = np.unique(v[np.isfinite(v)])
    if 1 < u.size <= bins:
        mid = (u[1:] + u[:-1]) / 2
        return np.r_[u[0] - (mid[0] - u[0]), mid, u[-1] + (u[-1] - mid[-1])]
    lo, hi = (u[0], u[-1]) if u.size else (0.0, 1.0)
    if lo == hi:
        lo, hi = lo - 0.5, hi + 0.5
    return np.linspace(lo, hi, bins + 1)


def binned_2d(x, y, z, x_edges, y_edges, statistic):
    """Per 2-D bin the ``statistic`` ("mean" or "median") of z over the points (x, y) in it: an
    array (x bins × y bins), NaN in empty bins. The bins are [e_i, e_{i+1}), the last one closed;
    points outside the edges are left out — as ``scipy.stats.binned_statistic_2d`` does, written
    with numpy's sort and bincount because the scipy function and its import took 1.7 s of a
    report page of 10⁶ designs (this one: 0.1–0.4 s)."""
    nx, ny = len(x_edges) - 1, len(y_edges) - 1
    ix, iy = _bin_index(x, x_edges), _bin_index(y, y_edges)
    inside = (ix >= 0) & (iy >= 0)
    flat, z = ix[inside] * ny + iy[inside], np.asarray(z, dtype=float)[inside]
    count = np.bincount(flat, minlength=nx * ny)
    out = np.full(nx * ny, np.nan)
    full = count > 0
    if statistic == "mean":
        out[full] = np.bincount(flat, weights=z, minlength=nx * ny)[full] / count[full]
    elif statistic == "median":
        by_value = np.argsort(z)
        zs = z[by_value[np.argsort(flat[by_value], kind="stable")]]  # by bin, then by value
        start = np.cumsum(count) - count
        lo = start + (count - 1) // 2
        hi = start + count // 2
        out[full] = 0.5 * (zs[lo[full]] + zs[hi[full]])
    else:
        raise ValueError(f"statistic {statistic!r}: 'mean' or 'median'")
    return out.reshape(nx, ny)


def _bin_index(v, edges):
    """The bin of each value ([e_i, e_{i+1}), the last closed), −1 outside the edges."""
    v = np.asarray(v, dtype=float)
    i = np.searchsorted(edges, v, side="right") - 1
    i[v == edges[-1]] = len(edges) - 2
    i[(i < 0) | (i > len(edges) - 2) | ~np.isfinite(v)] = -1
    return i


def sampled_category_map(ax, x, y, category, categories, bins=30):
    """Map of a sampled design over two factors: each design a marker coloured by its category
    (index into ``categories``, a tuple of (label, colour); the first is "passes") for up to
    :data:`SCATTER_MAX` designs, else per 2-D bin the share of designs in the first category (an
    image, so the page stays small and fast at 10⁶ designs). Returns the legend handles."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.lines import Line2D

    x, y, category = (np.asarray(v).reshape(-1) for v in (x, y, category))
    if x.size <= SCATTER_MAX:
        ax.scatter(
            x,
            y,
            c=category,
            s=14,
            cmap=ListedColormap([c for _, c in categories]),
            norm=BoundaryNorm(np.arange(len(categories) + 1) - 0.5, len(categories)),
            rasterized=True,
        )
        return [
            Line2D([], [], ls="", marker="s", color=c, ms=9, label=lab) for lab, c in categories
        ]
    xe, ye = _edges(x, bins), _edges(y, bins)
    share = binned_2d(x, y, (category == 0).astype(float), xe, ye, "mean")
    mesh = ax.pcolormesh(
        xe,
        ye,
        share.T,
        cmap="RdYlGn",
        vmin=0,
        vmax=1,
        rasterized=True,
    )
    ax.figure.colorbar(
        mesh, ax=ax, label=f"share of designs: {categories[0][0]} ({x.size} designs binned)"
    )
    return []


def texts_outside(fig) -> list[str]:
    """The texts of a figure (titles, labels, legends, table cells, notes; not tick labels, which
    matplotlib clips to the axes) that reach beyond the page."""
    import math

    from matplotlib.text import Text

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ticks = set()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            ticks |= {
                id(t)
                for tick in axis.get_major_ticks() + axis.get_minor_ticks()
                for t in (tick.label1, tick.label2)
            }
    width, height = fig.bbox.width, fig.bbox.height
    out = []
    for t in fig.findobj(Text):
        if id(t) in ticks or not t.get_visible() or not t.get_text().strip():
            continue
        bb = t.get_window_extent(renderer)
        if not all(map(math.isfinite, (bb.x0, bb.y0, bb.x1, bb.y1))):
            continue
        if bb.x0 < -1 or bb.y0 < -1 or bb.x1 > width + 1 or bb.y1 > height + 1:
            out.append(t.get_text())
    return out


def label_points(ax, points, fontsize=8.0):
    """Each point's label beside it: up and right of it, else below right, up left or below
    left, the first place clear of the texts already in ``ax``, its legend and the drawn points
    of its lines (else the one over the fewest of those points); a label that would overprint a
    text in each of those places is left out (its point stays drawn). ``points``: (x, y, text)
    in data coordinates, or (x, y, text, colour) to print it in its line's colour. Call once the
    axes' limits, legend and the figure's layout are final: the places are measured."""
    ax.get_xlim(), ax.get_ylim()  # (the limits autoscaled now: the labels' places follow them)
    renderer = ax.figure.canvas.get_renderer()
    placed = [t.get_window_extent(renderer) for t in ax.texts if t.get_text().strip()]
    if ax.get_legend() is not None:
        placed.append(ax.get_legend().get_window_extent(renderer))
    drawn_xy = [ln.get_transform().transform(ln.get_xydata()) for ln in ax.get_lines()]
    marks = np.concatenate(drawn_xy) if drawn_xy else np.zeros((0, 2))
    places = ((4, 4, "left"), (4, -11, "left"), (-4, 4, "right"), (-4, -11, "right"))
    for x, y, text, *colour in points:
        best = None  # (points under it, its place) of the places clear of the texts
        for dx, dy, ha in places:
            note = ax.annotate(
                text, (x, y), textcoords="offset points", xytext=(dx, dy), ha=ha,
                fontsize=fontsize, color=colour[0] if colour else "black",
            )  # fmt: skip
            box = note.get_window_extent(renderer)
            note.remove()
            if any(box.overlaps(b) for b in placed):
                continue
            under = int(_within(marks, box.padded(2.0)).sum())
            if best is None or under < best[0]:
                best = (under, (dx, dy, ha), box)
            if not under:
                break
        if best is not None:
            (dx, dy, ha), box = best[1], best[2]
            ax.annotate(
                text, (x, y), textcoords="offset points", xytext=(dx, dy), ha=ha,
                fontsize=fontsize, color=colour[0] if colour else "black",
            )  # fmt: skip
            placed.append(box)


def texts_overprinted(fig) -> list[tuple[str, str]]:
    """The pairs of texts placed in one axes (point labels, cell numbers, notes) that overprint
    each other by more than a pixel."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    out = []
    for ax in fig.axes:
        boxes = [
            (t.get_text(), t.get_window_extent(renderer).padded(-1.0))
            for t in ax.texts
            if t.get_visible() and t.get_text().strip()
        ]
        for i, (a, box_a) in enumerate(boxes):
            out += [(a, b) for b, box_b in boxes[i + 1 :] if box_a.overlaps(box_b)]
    return out


def texts_outside_cells(fig) -> list[str]:
    """The table cells of a figure whose text reaches beyond the cell (e.g. a wrapped column name
    taller than its row)."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    out = []
    for ax in fig.axes:
        for table in ax.tables:
            for cell in table.get_celld().values():
                text = cell.get_text()
                if not text.get_text().strip():
                    continue
                tb, cb = text.get_window_extent(renderer), cell.get_window_extent(renderer)
                if tb.x0 < cb.x0 - 1 or tb.x1 > cb.x1 + 1 or tb.y0 < cb.y0 - 1 or tb.y1 > cb.y1 + 1:
                    out.append(text.get_text())
    return out


def texts_too_small(fig, minimum=8.0) -> list[tuple[str, float]]:
    """The visible texts of a figure (tick labels included) set below ``minimum`` points: a page is
    A4 at 100 %, so a font size in points is the size on paper."""
    from matplotlib.text import Text

    fig.canvas.draw()
    return [
        (t.get_text(), t.get_fontsize())
        for t in fig.findobj(Text)
        if t.get_visible() and t.get_text().strip() and t.get_fontsize() < minimum - 1e-9
    ]


def status_categories(status, categories: dict, other: int) -> np.ndarray:
    """A category number per scenario from its status ({meaning: number}; ``other`` for the rest)."""
    status = np.asarray(status)
    cat = np.full(status.shape, other)
    for meaning, k in categories.items():
        cat[status == st.CODE[meaning]] = k
    return cat


def robust_limits(z, symmetric=False, cap=None):
    """Colour limits from the 1st and 99th percentiles of the finite values (a few near-singular
    designs, e.g. near a jam, must not set the scale), optionally symmetric about 0 or capped."""
    z = np.asarray(z, dtype=float)
    z = z[np.isfinite(z)]
    if z.size == 0:
        return (-1.0, 1.0) if symmetric else (0.0, 1.0)
    lo, hi = np.percentile(z, [1, 99])
    if symmetric:
        lim = max(abs(lo), abs(hi)) or 1.0
        return -lim, lim
    if cap is not None:
        hi = min(hi, cap)
    return float(lo), float(hi if hi > lo else lo + 1.0)


def colour_extend(z, vmin, vmax) -> str:
    """A colour bar's ``extend``: towards the ends that values of ``z`` lie beyond."""
    z = np.asarray(z, dtype=float)
    z = z[np.isfinite(z)]
    below, above = bool((z < vmin).any()), bool((z > vmax).any())
    return {(False, False): "neither", (True, False): "min", (False, True): "max"}.get(
        (below, above), "both"
    )


def sampled_value_map(ax, x, y, z, label, cmap="viridis", limits=None, bins=30):
    """Map of a sampled design's output over two factors: markers coloured by value for up to
    :data:`SCATTER_MAX` designs, else the median per 2-D bin (an image); colours clipped to
    ``limits`` (default :func:`robust_limits`), the colour bar extended where values lie beyond."""
    x, y, z = (np.asarray(v, dtype=float).reshape(-1) for v in (x, y, z))
    vmin, vmax = limits or robust_limits(z)
    finite = np.isfinite(z)
    extend = colour_extend(z, vmin, vmax)
    if x.size <= SCATTER_MAX:
        m = ax.scatter(
            x[finite],
            y[finite],
            c=z[finite],
            s=14,
            cmap=cmap,
            vmin=vmin,
            vmax=vmax,
            edgecolors="0.2",  # a pale end of the colour map stays visible on white
            linewidths=0.3,
            rasterized=True,
        )
    else:
        xe, ye = _edges(x[finite], bins), _edges(y[finite], bins)
        med = binned_2d(x[finite], y[finite], z[finite], xe, ye, "median")
        m = ax.pcolormesh(
            xe,
            ye,
            med.T,
            cmap=cmap,
            vmin=vmin,
            vmax=vmax,
            rasterized=True,
        )
        label += f"\n(median per bin, {x.size} designs)"
    ax.figure.colorbar(m, ax=ax, label=label, extend=extend)
    return m


# most markers a scatter layer draws; above, an even random subset (the same every run) stands for
# the designs, said on the page, so a page of 10^6 designs draws in about a second
DRAW_MAX = 20_000


def drawn(mask_or_n) -> np.ndarray:
    """Indices of the designs a scatter layer draws: all of them (a boolean mask's True entries,
    or range(n)) up to :data:`DRAW_MAX`, else a fixed random subset of that size, in order."""
    idx = np.flatnonzero(mask_or_n) if np.ndim(mask_or_n) else np.arange(int(mask_or_n))
    if idx.size <= DRAW_MAX:
        return idx
    return np.sort(np.random.default_rng(0).choice(idx, DRAW_MAX, replace=False))


def drawn_note(n: int) -> str:
    """'' or the page's note that a subset of the designs is drawn."""
    return "" if n <= DRAW_MAX else f" ({DRAW_MAX} of {n} designs drawn, chosen at random)"


_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def fold_multipliers(fig) -> None:
    """Put each labelled linear axis' power-of-ten multiplier into its label: ``peak_jerk
    [10⁶ rad/s³]`` and ticks 1-8, where matplotlib prints a bare "1e6" at the axis' end, which
    reads past (or as a tick). An additive offset is left as it is."""
    import math

    from matplotlib.ticker import FuncFormatter, ScalarFormatter

    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            fmt, label = axis.get_major_formatter(), axis.get_label_text()
            if not (label and isinstance(fmt, ScalarFormatter) and axis.get_scale() == "linear"):
                continue
            lo, hi = sorted(axis.get_view_interval())
            locs = [v for v in axis.get_majorticklocs() if lo <= v <= hi and v != 0]
            fmt.set_locs(locs)
            if not locs or not fmt.get_offset() or fmt.offset != 0:
                continue  # (no multiplier, or an additive offset)
            exp = math.floor(math.log10(max(abs(v) for v in locs)))
            power = "10" + str(exp).translate(_SUPERSCRIPT)
            if "[-]" in label:
                label = label.replace("[-]", f"[{power}]", 1)
            elif "[" in label:
                label = label.replace("[", f"[{power} ", 1)
            else:
                label = f"{label} [{power}]"
            axis.set_label_text(label)
            axis.set_major_formatter(FuncFormatter(lambda v, _, e=exp: f"{v / 10.0**e:g}"))


def legend_clear_of_data(fig, ax, most_inside=4) -> None:
    """The legend of a page's one panel: inside it (upper right) with at most ``most_inside``
    entries, else under the panel in two columns, the panel shortened to make room (a long
    legend inside hid the data)."""
    handles, labels = ax.get_legend_handles_labels()
    if len(handles) <= most_inside:
        ax.legend(loc="upper right", fontsize=8)
        return
    rows = -(-len(handles) // 2)
    line = 1.45 * 8 / 72 / fig.get_figheight()  # a legend row, as a share of the page
    fig.subplots_adjust(bottom=0.1 + rows * line)
    fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 0.01), ncol=2, fontsize=8)


def legends_over_data(fig, most=0) -> list[tuple[str, int]]:
    """The legends of a figure that cover plotted data: (its first entry, how many of the data
    points drawn under it, of the curves of three points or more and the scattered markers of
    every axes it overlaps), for each that covers more than ``most``."""
    from matplotlib.collections import PathCollection

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legends = [a.get_legend() for a in fig.axes if a.get_legend() is not None] + list(fig.legends)
    out = []
    for legend in legends:
        box = legend.get_window_extent(renderer).padded(-2.0)
        covered = 0
        for ax in fig.axes:
            frame = ax.get_window_extent(renderer)
            if not (ax.get_visible() and ax.axison and frame.overlaps(box)):
                continue
            points = [
                line.get_transform().transform(line.get_xydata())
                for line in ax.get_lines()
                if line.get_visible() and len(line.get_xdata()) >= 3
            ] + [
                c.get_offset_transform().transform(c.get_offsets())
                for c in ax.collections
                if isinstance(c, PathCollection) and c.get_visible() and len(c.get_offsets())
            ]
            for xy in points:
                xy = xy[np.isfinite(xy).all(axis=1)]
                inside = _within(xy, frame) & _within(xy, box)
                covered += int(inside.sum())
        if covered > most:
            texts = legend.get_texts()
            out.append((texts[0].get_text() if texts else "", covered))
    return out


def _within(xy, box):
    """Which display points ``xy`` (n × 2) lie inside the bounding box ``box``."""
    return (xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)


def wrap_even(text, width) -> list[str]:
    """``text`` wrapped to at most ``width`` characters a line in as few lines as textwrap takes,
    the lines of even length: a title's last word no longer hangs alone on its line."""
    lines = textwrap.wrap(text, width)
    if len(lines) < 2:
        return lines
    for w in range(-(-len(text) // len(lines)), width):
        even = textwrap.wrap(text, w)
        if len(even) == len(lines):
            return even
    return lines


def hatch_cells(ax, x, y, mask, label) -> int:
    """Hatch the cells of a map drawn with ``pcolormesh(x, y, z, shading="nearest")`` where
    ``mask`` (shaped like z: len(y) × len(x)) holds, the first named ``label`` in the legend.
    Returns how many."""
    from matplotlib.patches import Rectangle

    xe, ye = _edges(np.asarray(x, float), len(x)), _edges(np.asarray(y, float), len(y))
    for k, (j, i) in enumerate(zip(*np.nonzero(mask), strict=True)):
        cell = (xe[i], ye[j]), xe[i + 1] - xe[i], ye[j + 1] - ye[j]
        # a white hatch (seen on a dark cell) inside a red frame (seen on a light one)
        ax.add_patch(Rectangle(*cell, fill=False, hatch="///", edgecolor="w", lw=0))
        ax.add_patch(
            Rectangle(
                *cell, fill=False, edgecolor="tab:red", lw=1.5, label=label if k == 0 else None
            )
        )
    return int(np.count_nonzero(mask))

"""Report: figures and a PDF built from stored Datasets only (no solver is ever re-run).

:func:`build` writes one PNG per figure, ``report.pdf`` with every figure as a page, and
``validation.csv`` with every reproduced published number. It is :func:`study_part` for each study
(its pages, drawn once each for the PNG and the PDF, as a PDF part) and :func:`assemble` (the
summary and the run's pages; the parts joined by pypdf): the workflow runs each study's part as a
job of its own, beside the other studies' jobs, and only the assembly at the end.
"""

from __future__ import annotations

import importlib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.backends.backend_pdf import PdfPages  # noqa: E402

from .. import __version__, store, studies  # noqa: E402
from .. import status as st  # noqa: E402
from ..explore import refinement_gain  # noqa: E402
from ..robust import front_view as robust_front_view  # noqa: E402
from ..validation import to_csv  # noqa: E402
from . import answers  # noqa: E402
from .common import (  # noqa: E402
    fold_multipliers,
    hard_case_table,
    summary_layout,
    title_page,
    validation_table,
    wrap_even,
)

__all__ = [
    "assemble",
    "build",
    "figure_stems",
    "run_stems",
    "study_stems",
    "answer_files",
    "study_part",
    "study_pages",
    "study_page_stems",
]

# study name -> the module of this package that draws its pages (its ``PAGES``: stem -> function of
# the study's Dataset). The report looks figures up by study name; studies never import the report.
FIGURE_MODULES = {
    "diaphragm_spring": "diaphragm_figures",
    "engagement": "engagement_figures",
    "centrifugal": "centrifugal_figures",
    "sprag": "sprag_figures",
    "roller": "roller_figures",
}


def _pages_of(name: str) -> dict:
    try:
        module = FIGURE_MODULES[name]
    except KeyError:
        raise KeyError(
            f"no report pages for study {name!r}; known: {sorted(FIGURE_MODULES)}"
        ) from None
    return importlib.import_module(f".{module}", __name__).PAGES


def study_page_stems(name: str) -> tuple[str, ...]:
    """Stems of the study's own pages, in report order (without the answers and other pages)."""
    return tuple(_pages_of(name))


def study_pages(name: str, ds) -> list:
    """The study's own pages drawn from its stored Dataset: [(stem, Figure)] in report order."""
    return [(stem, draw(ds)) for stem, draw in _pages_of(name).items()]


def study_stems(name, sensitivity=False, refined=False, robust=False) -> list[str]:
    """PNG stems of one study's pages (its part of the report, :func:`study_part`), in order: a
    robust study's robust page first, its own pages, its answers, a factorial or saltelli study's
    sensitivity page, a refined study's refinement page."""
    return [
        f"{name}_{s}"
        for s in (
            *(["robust"] if robust else []),
            *study_page_stems(name),
            "answers",
            *(["sensitivity"] if sensitivity else []),
            *(["refinement"] if refined else []),
        )
    ]


def run_stems(study_names, benchmark=False, hard_cases=False, numerics=False) -> list[str]:
    """PNG stems of the report's pages that are not a study's, in the PDF's order: the summary
    first (:func:`assemble`), then the run's pages after the studies' (:func:`run_part`:
    work-precision, validation table, numerics, hard cases)."""
    from ..bench.numerics import stems as numerics_stems

    validated = any(studies.get(name).validation is not None for name in study_names)
    return (
        ["title"]
        + (["engagement_work_precision"] if benchmark else [])
        + (["validation_table"] if validated else [])
        + (numerics_stems(study_names) if numerics else [])
        + (["hard_cases"] if hard_cases else [])
    )


def figure_stems(
    study_names,
    benchmark=False,
    sensitivity=(),
    refined=(),
    hard_cases=False,
    numerics=False,
    robust=(),
) -> list[str]:
    """PNG stems the report produces for these studies, in the PDF's order; a sensitivity page
    for the studies in ``sensitivity`` (factorial grids), a refinement page for those in ``refined``
    (design refine); the validation table only where one of them reproduces published numbers; the
    work-precision pages of the solvers used with ``numerics``; the hard-case table with
    ``hard_cases``."""
    run = run_stems(study_names, benchmark, hard_cases, numerics)
    return (
        run[:1]
        + [
            stem
            for name in study_names
            for stem in study_stems(name, name in sensitivity, name in refined, name in robust)
        ]
        + run[1:]
    )


def answer_files(study_names, refined=(), robust=()) -> list[str]:
    """The front tables the report writes (one CSV per study), the refinement tables and the
    robust fronts."""
    return (
        [f"{name}_pareto.csv" for name in study_names]
        + [f"{name}_refinement.csv" for name in refined]
        + [f"{name}_robust.csv" for name in study_names if name in robust]
    )


class Page:
    """A report page: its PNG stem, a function drawing it, and (tables) the A4 pages that stand for
    it in the PDF: a table longer than a page is one tall PNG and several PDF pages."""

    def __init__(self, stem, draw, pdf_pages=None, n_pdf=1):
        self.stem, self.draw, self.pdf_pages, self.n_pdf = stem, draw, pdf_pages, n_pdf


def _study_pages(
    name, ds, sensitivity, refine, outdir, robust=None, first_robust=None
) -> list[Page]:
    """A study's pages (drawn later, one at a time) and its CSV files (written now); a sensitivity
    page from ``sensitivity`` (a path), a refinement page against the first-stage result
    ``refine`` (a path); a robust study's robust answers (``robust``) lead; a refined robust
    study's refinement compares its robust front with the first stage's (``first_robust``)."""
    from functools import partial

    from . import robust as robust_pages

    pages = []
    if robust is not None:
        pages.append(Page(f"{name}_robust", partial(robust_pages.page, name, robust)))
        with store.atomic(outdir / f"{name}_robust.csv") as tmp:
            robust_pages.write_csv(robust, tmp)
    pages += [Page(f"{name}_{stem}", partial(draw, ds)) for stem, draw in _pages_of(name).items()]
    pages.append(Page(f"{name}_answers", partial(answers.page, name, ds)))
    if sensitivity is not None:
        se = store.load(sensitivity)
        pages.append(Page(f"{name}_sensitivity", partial(answers.sensitivity_page, name, se)))
    with store.atomic(outdir / f"{name}_pareto.csv") as tmp:
        answers.write_csv(ds, tmp)
    if refine is not None:
        first, second = store.load(refine), ds
        if robust is not None and first_robust is not None:
            first = robust_front_view(first_robust, first.attrs)
            second = robust_front_view(robust, ds.attrs)
        gain = refinement_gain(first, second)
        pages.append(
            Page(f"{name}_refinement", partial(answers.refinement_page, name, first, second, gain))
        )
        with store.atomic(outdir / f"{name}_refinement.csv") as tmp:
            answers.write_refinement_csv(gain, tmp)
    return pages


def _table_page(stem, table) -> Page:
    """A table (:class:`clutchlab.report.common.Table`) as one PNG and its A4 PDF pages."""
    return Page(stem, table.figure, table.pages, table.n_pages)


def study_part(
    name,
    result,
    outdir,
    part_pdf,
    *,
    dpi=120,
    sensitivity=None,
    refine=None,
    traces=None,
    robust=None,
    refine_robust=None,
    explorer=None,
) -> dict:
    """Draw one study's pages: each page once, as its PNG in ``outdir`` and its page(s) of the
    study's PDF part; its CSV files in ``outdir``; optionally its explorer. The report's other
    pages and the whole PDF are :func:`assemble`'s (the workflow draws each study's part in a job
    of its own, beside the other studies').

    Parameters
    ----------
    name : str
        The study.
    result : path or xarray.Dataset
        Its merged HDF5 result (or the result loaded, e.g. by :func:`clutchlab.verify.load_checked`).
    outdir : path
        Folder of the report's PNG and CSV files.
    part_pdf : path
        The study's pages as a PDF, in report order; :func:`assemble` joins the parts. Beside it,
        ``<part_pdf stem>.json``: the part's record (this function's return value).
    dpi : int
        Resolution of the PNGs.
    sensitivity, refine, traces, robust, refine_robust : path or None
        The study's ``sensitivity.h5``, the first-stage result a ``design: refine`` study refined,
        its ``traces.h5``, its ``robust.h5`` and the first stage's robust answers (as in
        :func:`build`).
    explorer : path or None
        Where to write the study's explorer (:mod:`clutchlab.report.explorer`), if anywhere.

    Returns
    -------
    dict
        The part's record: ``study``, ``pages`` ([stem, PDF pages] in order), ``files`` (its CSV
        files), ``summary`` (:func:`clutchlab.report.common.study_summary`) and
        ``result_checksum`` (the stored checksum of the result it was drawn from).
    """
    from .. import traces as tr
    from .common import study_summary

    outdir, part_pdf = Path(outdir), Path(part_pdf)
    outdir.mkdir(parents=True, exist_ok=True)
    part_pdf.parent.mkdir(parents=True, exist_ok=True)
    ds = result if hasattr(result, "attrs") else store.load(result)
    checksum = str(ds.attrs.get(store.CHECKSUM, ""))  # (the file's, as loaded)
    if explorer is not None:
        from . import explorer as explorer_page

        explorer_page.write_dataset(ds, explorer)
    if traces is not None:
        ds = tr.attach(ds, store.load(traces))
    robust = store.load(robust) if robust is not None else None
    first_robust = store.load(refine_robust) if refine_robust is not None else None
    pages = _study_pages(name, ds, sensitivity, refine, outdir, robust, first_robust)
    _write_pages(pages, outdir, part_pdf, name, dpi)
    record = {
        "study": name,
        "pages": [[page.stem, page.n_pdf] for page in pages],
        "files": answer_files([name], [name] * (refine is not None), [name] * (robust is not None)),
        "summary": study_summary(name, ds, robust),
        "result_checksum": checksum,
    }
    _write_record(part_pdf, record)
    return record


def assemble(
    parts: list,
    validation_files: list,
    outdir,
    *,
    title="clutchlab report",
    dpi=120,
    benchmark_csv=None,
    hard_cases_file=None,
    numerics_dir=None,
    job_seconds=None,
    explorers=None,
    results=None,
    run_part_pdf=None,
) -> list[Path]:
    """The report from the studies' parts (:func:`study_part`) and the run's part
    (:func:`run_part`): the summary page as its PNG, and ``report.pdf``: the summary, every
    study's part in the order of ``parts``, then the run's pages. Parameters as :func:`build`;
    ``parts``: the parts' PDF files (each with its record beside it); ``results``: the studies'
    results in place, in the order of ``parts`` (each part must have been drawn from it: its
    stored checksum, else :class:`clutchlab.verify.ProvenanceError` before anything is written);
    ``run_part_pdf``: the run's part, drawn by :func:`run_part` beforehand (the workflow's job
    ``run_pages``), else drawn here from ``benchmark_csv``, ``hard_cases_file`` and
    ``numerics_dir``. PNG and CSV files in ``outdir`` that neither this nor a part wrote are
    removed.

    Returns
    -------
    list of Path
        The PNGs of every page, in the PDF's order, and ``report.pdf``.
    """
    import io
    import tempfile

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    records = [_record_of(p) for p in parts]
    _check_parts(parts, records, results)
    validations = [store.load(p) for p in validation_files]
    studies = [r["study"] for r in records]
    with tempfile.TemporaryDirectory() as folder:
        if run_part_pdf is None:
            run_part_pdf = Path(folder) / "run_pages.pdf"
            run_part(
                outdir,
                run_part_pdf,
                validation_files,
                studies=studies,
                dpi=dpi,
                benchmark_csv=benchmark_csv,
                numerics_dir=numerics_dir,
                hard_cases_file=hard_cases_file,
            )
        run = _record_of(run_part_pdf)
        # the summary opens the report (on more than one page where its lines need them)
        counts = [tuple(s) for r in [*records, run] for s in r["pages"]]
        summary = _summary_page(
            title, [r["summary"] for r in records], validations, counts, job_seconds, explorers
        )
        own = io.BytesIO()
        _write_pages([summary], outdir, own, title, dpi)
        joined = list(parts) + ([run_part_pdf] if run["pages"] else [])
        _join(own, joined, title, outdir / "report.pdf")
    stems = ["title"] + [s for r in [*records, run] for s, _ in r["pages"]]
    written = [outdir / f"{stem}.png" for stem in stems]
    tables = [f for r in [*records, run] for f in r["files"]]
    _remove_stale(outdir, [p.name for p in written] + tables, explorers)
    return written + [outdir / "report.pdf"]


def run_part(
    outdir,
    part_pdf,
    validation_files=(),
    *,
    studies=(),
    dpi=120,
    benchmark_csv=None,
    numerics_dir=None,
    hard_cases_file=None,
) -> dict:
    """Draw the run's pages after the studies' (work-precision, validation table, the numerics of
    ``studies``, hard cases): each page once, as its PNG in ``outdir`` and its page(s) of the
    run's PDF part, with their CSV files (``validation.csv``, ``hard_cases.csv``). The workflow
    draws it in a job of its own as soon as its inputs exist, so that the report job at the end
    of a run only draws the summary and joins the parts (:func:`assemble`).

    Parameters
    ----------
    outdir : path
        Folder of the report's PNG and CSV files.
    part_pdf : path
        The run's pages as a PDF (not written where there are none); beside it,
        ``<part_pdf stem>.json``: the part's record (this function's return value).
    validation_files : list of path
        The validation Datasets (one per seed): the validation table.
    studies : list of str
        The studies of the run (the numerics pages of those).
    dpi : int
        Resolution of the PNGs.
    benchmark_csv, numerics_dir, hard_cases_file : path or None
        As :func:`build`.

    Returns
    -------
    dict
        The part's record: ``pages`` ([stem, PDF pages] in order) and ``files`` (its CSV files).
    """
    outdir, part_pdf = Path(outdir), Path(part_pdf)
    outdir.mkdir(parents=True, exist_ok=True)
    part_pdf.parent.mkdir(parents=True, exist_ok=True)
    validations = [store.load(p) for p in validation_files]
    pages = _run_pages(
        outdir, validations, benchmark_csv, numerics_dir, hard_cases_file, list(studies)
    )
    if pages:
        _write_pages(pages, outdir, part_pdf, "clutchlab: the run's pages", dpi)
    record = {
        "pages": [[page.stem, page.n_pdf] for page in pages],
        "files": ["validation.csv"] * bool(validations)
        + ["hard_cases.csv"] * (hard_cases_file is not None),
    }
    _write_record(part_pdf, record)
    return record


def _write_record(part_pdf, record: dict) -> None:
    """A report part's record, ``<part_pdf stem>.json`` beside it (written atomically)."""
    import json

    with store.atomic(Path(part_pdf).with_suffix(".json")) as tmp:
        Path(tmp).write_text(json.dumps(record, indent=1), encoding="utf-8")


def _record_of(part_pdf) -> dict:
    """The record beside a report part (:func:`_write_record`)."""
    import json

    return json.loads(Path(part_pdf).with_suffix(".json").read_text("utf-8"))


def _summary_page(title, summaries, validations, counts, job_seconds, explorers) -> Page:
    """The summary as a page of the report: it names each page by its numbers (``counts``: stem ->
    PDF pages, in order after it), which follow the summary's own pages, which follow its text."""
    n_title = 1
    for _ in range(3):
        numbers, k = {}, 1 + n_title
        for stem, n_pdf in counts:
            numbers[stem], k = (k, k + n_pdf - 1), k + n_pdf
        n = len(summary_layout(title, summaries, validations, numbers, job_seconds, explorers)[2])
        if n == n_title:
            break
        n_title = n
    args = (title, __version__, summaries, validations, numbers, job_seconds, explorers)
    pdf_pages = (
        (lambda: [title_page(*args, page=i) for i in range(n_title)]) if n_title > 1 else None
    )
    return Page("title", lambda: title_page(*args), pdf_pages, n_title)


def _join(own, parts, title, path) -> None:
    """``report.pdf``: the pages of ``own`` (the summary), then every part in order."""
    from pypdf import PdfReader, PdfWriter

    writer = PdfWriter()
    for page in PdfReader(own).pages:
        writer.add_page(page)
    for part in parts:
        writer.append(str(part))
    writer.add_metadata({"/Title": title, "/Creator": f"clutchlab {__version__}"})
    with store.atomic(path) as tmp:
        writer.write(tmp)


def _check_parts(parts, records, results) -> None:
    """Each part was drawn from the result now in place (the checksum it recorded is the file's)."""
    from ..verify import ProvenanceError

    if results is None:
        return
    bad = [
        f"{part} was drawn from another {result} than the one in place; delete it and run "
        "snakemake again to draw it anew"
        for part, record, result in zip(parts, records, results, strict=True)
        if record["result_checksum"] != store.stored_checksum(result)
    ]
    if bad:
        raise ProvenanceError("\n".join(bad))


def build(
    study_files: dict,
    validation_files: list,
    outdir,
    *,
    title="clutchlab report",
    dpi=120,
    benchmark_csv=None,
    sensitivity_files=None,
    refine_files=None,
    hard_cases_file=None,
    numerics_dir=None,
    job_seconds=None,
    traces_files=None,
    robust_files=None,
    refine_robust_files=None,
    explorers=None,
) -> list[Path]:
    """Build the report from stored results in one call: each study's part (:func:`study_part`),
    then :func:`assemble` (the workflow runs the parts as jobs of their own).

    Parameters
    ----------
    study_files : dict
        Study name -> path of its merged HDF5 result.
    validation_files : list
        Paths of validation Datasets (one per seed).
    benchmark_csv : path or None
        ``engagement_benchmark.csv`` of :mod:`clutchlab.bench.engagement`: adds the work-precision page.
    sensitivity_files : dict or None
        Study name -> its ``sensitivity.h5`` (factorial studies): adds a sensitivity page.
    refine_files : dict or None
        Study name -> the first-stage result a ``design: refine`` study refined: adds a page with
        the hypervolume before and after, and ``<study>_refinement.csv``.
    hard_cases_file : path or None
        The hard cases computed in this run (:mod:`clutchlab.hardcases`): adds their table page
        and ``hard_cases.csv``.
    numerics_dir : path or None
        The folder of this run's small solver benchmarks (:mod:`clutchlab.bench.numerics`): adds a
        work-precision page per solver.
    job_seconds : dict or None
        Study name -> (chunk jobs, their seconds and the merge's), from Snakemake's benchmark
        files: the summary page says how long each study took.
    traces_files : dict or None
        Study name -> its ``traces.h5`` (:mod:`clutchlab.traces`): the traces of the design its
        pages show. Without one, a study's pages compute nothing: they take the traces already in
        its Dataset (an in-memory :func:`clutchlab.pipeline.run_study`), if any.
    robust_files : dict or None
        Study name -> its ``robust.h5`` (a robust study's answers, :func:`clutchlab.explore.robust`):
        its robust page leads its pages, the summary leads with its robust front, and
        ``<study>_robust.csv`` lists the robust front designs.
    refine_robust_files : dict or None
        Study name -> the ``robust.h5`` beside the first-stage result a refined robust study
        started from: its refinement page compares robust fronts (worst case or quantile over
        conditions and noise, robust-feasible designs) instead of per-condition fronts.
    explorers : dict or None
        Study name -> the file name of its explorer (:mod:`clutchlab.report.explorer`) in
        ``outdir``: the summary page links it. Given, explorers of other studies in ``outdir``
        (an earlier run of another config) are removed.
    outdir : path
        Folder for ``report.pdf``, ``validation.csv`` and the PNGs. PNG and CSV files in it that
        this report does not write (pages of an earlier run of another config) are removed.

    Returns
    -------
    list of Path
        The PNGs written, in the PDF's order, and ``report.pdf``.
    """
    import tempfile

    def given(files, name):
        return (files or {}).get(name)

    with tempfile.TemporaryDirectory() as folder:
        parts = []
        for name, path in study_files.items():
            parts.append(Path(folder) / f"{name}.pdf")
            study_part(
                name,
                path,
                outdir,
                parts[-1],
                dpi=dpi,
                sensitivity=given(sensitivity_files, name),
                refine=given(refine_files, name),
                traces=given(traces_files, name),
                robust=given(robust_files, name),
                refine_robust=given(refine_robust_files, name),
            )
        return assemble(
            parts,
            validation_files,
            outdir,
            results=list(study_files.values()),
            title=title,
            dpi=dpi,
            benchmark_csv=benchmark_csv,
            hard_cases_file=hard_cases_file,
            numerics_dir=numerics_dir,
            job_seconds=job_seconds,
            explorers=explorers,
        )


def _run_pages(
    outdir, validations, benchmark_csv, numerics_dir, hard_cases_file, studies
) -> list[Page]:
    """The pages of the run after the studies' (work-precision, validation table, the numerics of
    ``studies``, hard cases), and their CSV files (written now)."""
    pages = []
    if benchmark_csv is not None:
        from ..bench.engagement import read_rows, work_precision_figure

        rows = read_rows(benchmark_csv)
        pages.append(Page("engagement_work_precision", lambda: work_precision_figure(rows)))
    if validations:
        pages.append(_table_page("validation_table", validation_table(validations)))
        with store.atomic(outdir / "validation.csv") as tmp:
            to_csv(validations, tmp)
    if numerics_dir is not None:
        from ..bench.numerics import pages as numerics_pages

        pages += [
            Page(stem, (lambda f=fig: f)) for stem, fig in numerics_pages(numerics_dir, studies)
        ]
    if hard_cases_file is not None:
        from ..hardcases import to_csv as hard_cases_csv

        cases = store.load(hard_cases_file)
        pages.append(_table_page("hard_cases", hard_case_table(cases)))
        with store.atomic(outdir / "hard_cases.csv") as tmp:
            hard_cases_csv(cases, tmp)
    return pages


def _write_pages(pages, outdir, pdf_file, title, dpi) -> None:
    """Draw each page once, write its PNG and its PDF page(s) (to ``pdf_file``: a path, written
    atomically, or a binary file object), close it: one figure open at a time."""
    import contextlib

    with contextlib.ExitStack() as stack:
        if isinstance(pdf_file, (str, Path)):
            pdf_file = stack.enter_context(store.atomic(Path(pdf_file)))
        metadata = {"Title": title, "Creator": f"clutchlab {__version__}"}
        pdf = stack.enter_context(
            PdfPages(pdf_file, metadata={**metadata, "CreationDate": None, "ModDate": None})
        )
        for page in pages:
            # (a table's figure: its one tall PNG; its PDF pages are figures of their own)
            fig = page.draw()
            _wrap_suptitle(fig)
            fold_multipliers(fig)
            with store.atomic(outdir / f"{page.stem}.png") as tmp:
                fig.savefig(tmp, dpi=dpi, metadata={"Software": None}, format="png")
            if page.pdf_pages is None:
                pdf.savefig(fig)
            plt.close(fig)
            for part in page.pdf_pages() if page.pdf_pages is not None else ():
                _wrap_suptitle(part)
                pdf.savefig(part)
                plt.close(part)


def _remove_stale(outdir, keep, explorers=None) -> None:
    """Remove the PNG and CSV files of ``outdir`` that this report did not write (the pages of
    another config run into the same folder earlier), so the folder holds this run's report; with
    ``explorers`` (study -> file name) also the explorers of other studies."""
    keep = set(keep) | set((explorers or {}).values())
    for path in outdir.iterdir():
        stale = path.suffix in (".png", ".csv") or (
            explorers is not None and path.name.endswith("_explorer.html")
        )
        if stale and path.name not in keep and path.is_file():
            path.unlink()


def _wrap_suptitle(fig, width=130):
    """Wrap a figure's title lines to the page (a long fixed-value list ran off both sides)."""
    title = getattr(fig, "_suptitle", None)
    if title is not None:
        title.set_text(
            "\n".join("\n".join(wrap_even(line, width)) for line in title.get_text().split("\n"))
        )


def status_counts(ds) -> dict[str, int]:
    """Scenario count per status meaning."""
    import numpy as np

    codes, counts = np.unique(ds["status"].values, return_counts=True)
    return {st.FLAGS.get(int(c), str(c)): int(n) for c, n in zip(codes, counts, strict=False)}

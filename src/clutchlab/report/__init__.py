"""Report: figures and a PDF built from stored Datasets only (no solver is ever re-run).

:func:`build` writes one PNG per figure, ``report.pdf`` with every figure as a page, and
``validation.csv`` with every reproduced published number.
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
from .common import hard_case_table, title_page, validation_table  # noqa: E402

__all__ = ["build", "figure_stems", "answer_files", "study_pages", "study_page_stems"]

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


def figure_stems(
    study_names,
    benchmark=False,
    sensitivity=(),
    refined=(),
    hard_cases=False,
    numerics=False,
    robust=(),
) -> list[str]:
    """PNG stems the report produces for these studies (for Snakemake outputs); a sensitivity page
    for the studies in ``sensitivity`` (factorial grids), a refinement page for those in ``refined``
    (design refine); the validation table only where one of them reproduces published numbers; the
    hard-case table with ``hard_cases``; the work-precision pages of the solvers used with ``numerics``."""
    from ..bench.numerics import stems as numerics_stems

    stems = ["title"] + [
        f"{name}_{s}"
        for name in study_names
        for s in (
            *(["robust"] if name in robust else []),
            *study_page_stems(name),
            "answers",
            *(["sensitivity"] if name in sensitivity else []),
            *(["refinement"] if name in refined else []),
        )
    ]
    validated = any(studies.get(name).validation is not None for name in study_names)
    return (
        stems
        + (["engagement_work_precision"] if benchmark else [])
        + (["validation_table"] if validated else [])
        + (["hard_cases"] if hard_cases else [])
        + (numerics_stems(study_names) if numerics else [])
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
    name, ds, sensitivity_files, refine_files, outdir, robust=None, first_robust=None
) -> list[Page]:
    """A study's pages (drawn later, one at a time) and its CSV files (written now); a robust
    study's robust answers (``robust``) lead; a refined robust study's refinement compares its
    robust front with the first stage's (``first_robust``)."""
    from functools import partial

    from . import robust as robust_pages

    pages = []
    if robust is not None:
        pages.append(Page(f"{name}_robust", partial(robust_pages.page, name, robust)))
        with store.atomic(outdir / f"{name}_robust.csv") as tmp:
            robust_pages.write_csv(robust, tmp)
    pages += [Page(f"{name}_{stem}", partial(draw, ds)) for stem, draw in _pages_of(name).items()]
    pages.append(Page(f"{name}_answers", partial(answers.page, name, ds)))
    if name in sensitivity_files:
        se = store.load(sensitivity_files[name])
        pages.append(Page(f"{name}_sensitivity", partial(answers.sensitivity_page, name, se)))
    with store.atomic(outdir / f"{name}_pareto.csv") as tmp:
        answers.write_csv(ds, tmp)
    if name in refine_files:
        first, second = store.load(refine_files[name]), ds
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
    processes=1,
) -> list[Path]:
    """Build the report from stored results.

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
    processes : int
        2 or more: the PNGs are written by a second (forked) process while this one writes the
        PDF (each page is drawn in both; about 40 % less wall time where a second core is free).
    outdir : path
        Folder for ``report.pdf``, ``validation.csv`` and the PNGs. PNG and CSV files in it that
        this report does not write (pages of an earlier run of another config) are removed.

    Returns
    -------
    list of Path
        The PNGs written and ``report.pdf``.
    """
    from .. import traces as tr

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    results = {name: store.load(p) for name, p in study_files.items()}
    for name, path in (traces_files or {}).items():
        results[name] = tr.attach(results[name], store.load(path))
    validations = [store.load(p) for p in validation_files]
    robust = {name: store.load(p) for name, p in (robust_files or {}).items()}
    first_robust = {name: store.load(p) for name, p in (refine_robust_files or {}).items()}
    pages = []
    for name, ds in results.items():
        pages += _study_pages(
            name,
            ds,
            sensitivity_files or {},
            refine_files or {},
            outdir,
            robust.get(name),
            first_robust.get(name),
        )
    pages += _run_pages(outdir, validations, benchmark_csv, numerics_dir, hard_cases_file)
    # the summary page opens the report and names each study's pages by their page numbers
    numbers, k = {}, 2
    for page in pages:
        numbers[page.stem] = (k, k + page.n_pdf - 1)
        k += page.n_pdf
    pages.insert(
        0,
        Page(
            "title",
            lambda: title_page(
                title, __version__, results, validations, numbers, job_seconds, robust, explorers
            ),
        ),
    )
    written = _write_pages(pages, outdir, title, dpi, processes)
    tables = answer_files(results, refine_files or {}, robust) + (
        ["validation.csv"] if validations else []
    )
    _remove_stale(
        outdir,
        [p.name for p in written] + tables + ["hard_cases.csv"] * bool(hard_cases_file),
        explorers,
    )
    return written + [outdir / "report.pdf"]


def _run_pages(outdir, validations, benchmark_csv, numerics_dir, hard_cases_file) -> list[Page]:
    """The pages of the run after the studies' (work-precision, validation table, numerics, hard
    cases), and their CSV files (written now)."""
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

        pages += [Page(stem, (lambda f=fig: f)) for stem, fig in numerics_pages(numerics_dir)]
    if hard_cases_file is not None:
        from ..hardcases import to_csv as hard_cases_csv

        cases = store.load(hard_cases_file)
        pages.append(_table_page("hard_cases", hard_case_table(cases)))
        with store.atomic(outdir / "hard_cases.csv") as tmp:
            hard_cases_csv(cases, tmp)
    return pages


def _write_pages(pages, outdir, title, dpi, processes=1) -> list[Path]:
    """Draw each page, write its PNG and its PDF page(s), close it: one figure open at a time.
    With ``processes`` 2 a forked process draws every page for its PNG while this one draws it
    again for the PDF (each half the writing: about 40 % less wall time for the report)."""
    import multiprocessing

    png_job = None
    # (fork: the child inherits the pages and their data, nothing is pickled)
    if processes > 1 and "fork" in multiprocessing.get_all_start_methods():
        png_job = multiprocessing.get_context("fork").Process(
            target=_write_pngs, args=(pages, outdir, dpi), daemon=True
        )  # (daemon: ended with this process if its PDF fails first)
        png_job.start()
    with (
        store.atomic(outdir / "report.pdf") as tmp_pdf,
        PdfPages(
            tmp_pdf,
            metadata={
                "Title": title,
                "Creator": f"clutchlab {__version__}",
                "CreationDate": None,
                "ModDate": None,
            },
        ) as pdf,
    ):
        for page in pages:
            fig = None  # (a table's PNG only: its PDF pages are figures of their own)
            if png_job is None or page.pdf_pages is None:
                fig = page.draw()
                _wrap_suptitle(fig)
            if png_job is None:
                _save_png(fig, page.stem, outdir, dpi)
            if page.pdf_pages is None:
                pdf.savefig(fig)
            if fig is not None:
                plt.close(fig)
            for part in page.pdf_pages() if page.pdf_pages is not None else ():
                _wrap_suptitle(part)
                pdf.savefig(part)
                plt.close(part)
        if png_job is not None:
            png_job.join()
            if png_job.exitcode != 0:
                raise RuntimeError(f"the report's PNG pages failed (exit code {png_job.exitcode})")
    return [outdir / f"{page.stem}.png" for page in pages]


def _save_png(fig, stem, outdir, dpi) -> None:
    with store.atomic(outdir / f"{stem}.png") as tmp:
        fig.savefig(tmp, dpi=dpi, metadata={"Software": None}, format="png")


def _write_pngs(pages, outdir, dpi) -> None:
    """Every page's PNG (the forked process of :func:`_write_pages`)."""
    for page in pages:
        fig = page.draw()
        _wrap_suptitle(fig)
        _save_png(fig, page.stem, outdir, dpi)
        plt.close(fig)


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
        import textwrap

        title.set_text(
            "\n".join(textwrap.fill(line, width) for line in title.get_text().split("\n"))
        )


def status_counts(ds) -> dict[str, int]:
    """Scenario count per status meaning."""
    import numpy as np

    codes, counts = np.unique(ds["status"].values, return_counts=True)
    return {st.FLAGS.get(int(c), str(c)): int(n) for c, n in zip(codes, counts, strict=False)}

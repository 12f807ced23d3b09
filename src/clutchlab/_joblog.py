"""A workflow job's log file: what a job script prints goes to its log (Snakemake's ``log:``) as
well as to the terminal, and so does the reason it stopped (its ``SystemExit`` message or its
traceback), so a failed job of a cluster run can be read afterwards."""

from __future__ import annotations

import contextlib
import sys
import traceback

__all__ = ["job_log"]


class _Tee:
    """A text stream that writes to several (the terminal's and the log's)."""

    def __init__(self, *streams):
        self.streams = streams

    def write(self, text):
        for stream in self.streams:
            stream.write(text)
        return len(text)

    def flush(self):
        for stream in self.streams:
            stream.flush()

    def __getattr__(self, name):  # fileno, encoding, isatty: the terminal's
        return getattr(self.streams[0], name)


@contextlib.contextmanager
def job_log(path):
    """Copy ``sys.stdout`` and ``sys.stderr`` to the log file ``path`` (UTF-8, replaced) while
    the block runs; a ``SystemExit`` message or an exception's traceback that ends the block is
    written to the log too, then raised as before (the terminal still shows it)."""
    with open(path, "w", encoding="utf-8") as log:
        out, err = sys.stdout, sys.stderr
        sys.stdout, sys.stderr = _Tee(out, log), _Tee(err, log)
        try:
            yield log
        except SystemExit as exc:
            if exc.code is not None and not isinstance(exc.code, int):
                print(exc.code, file=log)
            raise
        except BaseException:
            traceback.print_exc(file=log)
            raise
        finally:
            sys.stdout, sys.stderr = out, err

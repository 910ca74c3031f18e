"""Progress of a long command on stderr: a tqdm bar on a terminal, a line per stage otherwise.

One reporter for every command that can run for more than a few seconds, so that none is silent::

    reporter = Progress(not args.no_progress and not args.json, what="contact")
    try:
        r = steady_state(model, method, steps, progress=reporter.cycle)
        reporter.stage("writing the figures")
        ...
    finally:
        reporter.close()

``reporter.cycle`` takes the record that :func:`lcpfric.steady_state` passes to its
``progress`` callable after each cycle (:class:`lcpfric.periodic.driver.CycleProgress`: its
``cycle``, ``change``, ``tol`` and ``max_cycles``); ``reporter.stage(text)`` announces a step
of the command (a model being built, figures being written).

Where it writes
---------------
* **A terminal** (stderr is a tty) with ``tqdm`` installed: the cycles advance a bar, as the
  sweep's bar does (:func:`lcpfric.analysis.sweep._progress_bar`: on ``sys.stderr``,
  ``dynamic_ncols``), with the last residual and the tolerance after it; the bar shows only
  once the cycles have run for :data:`DELAY` seconds, so a quick run draws nothing. A stage is
  a line of its own.
* **Anything else** (a log file, a pipe, a batch job; or no ``tqdm``): one line per stage,
  ``contact: writing the figures``, and one per cycle, ``contact: cycle 3: residual 2.1e-04
  (tol 1e-10)`` (the first, which has no residual yet: ``contact: cycle 1 of at most 200 (tol
  1e-10)``). Cycle lines start once the reporter has lived :data:`DELAY` seconds and come at
  most one per :data:`INTERVAL` seconds; the last cycle is always written at the end if any
  earlier one was. A stage line is written at once.
* **Disabled** (``--no-progress``, ``--json``): nothing, and each call returns at once.

Only stderr is written, never stdout. Like every ``lcpfric.cli`` module this one imports only
the standard library at module level (``tqdm`` is imported on a terminal only).
"""

from __future__ import annotations

import math
import sys
import time

__all__ = ["Progress", "DELAY", "INTERVAL"]

#: seconds before the first cycle is reported (quick runs report nothing)
DELAY = 2.0
#: fewest seconds between two cycle lines when stderr is not a terminal
INTERVAL = 1.0


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        return False


def _tqdm():
    """``tqdm.tqdm``, or None if it is not installed."""
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm


class Progress:
    """The progress report of a command on stderr.

    Parameters
    ----------
    enabled : bool
        Report anything at all; False makes every call a no-op (``--no-progress``).
    what : str
        What runs, the bar's label and the prefix of each line (``"contact"``).
    stream : file, optional
        Where to write (default: ``sys.stderr`` at the time of writing).
    delay : float, optional
        Seconds before the first cycle is reported (default: :data:`DELAY`, read when the
        reporter is made, so that a test may set it to 0).
    interval : float, optional
        Fewest seconds between two cycle lines without a terminal (default: :data:`INTERVAL`).

    Examples
    --------
    >>> import io
    >>> from lcpfric.periodic.driver import CycleProgress
    >>> log = io.StringIO()
    >>> reporter = Progress(True, what="contact", stream=log, delay=0.0, interval=0.0)
    >>> reporter.cycle(CycleProgress(1, float("inf"), 1e-10, 200, 0.5))
    >>> reporter.cycle(CycleProgress(2, 2.1e-4, 1e-10, 200, 0.5))
    >>> reporter.stage("writing the figures")
    >>> reporter.close()
    >>> print(log.getvalue(), end="")
    contact: cycle 1 of at most 200 (tol 1e-10)
    contact: cycle 2: residual 2.1e-04 (tol 1e-10)
    contact: writing the figures
    """

    def __init__(
        self,
        enabled: bool = True,
        what: str = "",
        *,
        stream=None,
        delay: float | None = None,
        interval: float | None = None,
    ):
        self.enabled = bool(enabled)
        self.what = str(what)
        self._stream = stream
        self._delay = float(DELAY if delay is None else delay)
        self._interval = float(INTERVAL if interval is None else interval)
        self._start = time.monotonic()
        self._use_bar = None  # decided on the first cycle
        self._bar = None
        self._written_at = -math.inf  # when the last cycle line was written
        self._pending = None  # the last cycle line, not written yet
        self._lines = 0  # cycle lines written

    @property
    def stream(self):
        """Where the report goes."""
        return self._stream if self._stream is not None else sys.stderr

    def _write(self, text: str) -> None:
        print(f"{self.what}: {text}" if self.what else text, file=self.stream, flush=True)

    def stage(self, text: str) -> None:
        """Announce a step of the command, on a line of its own at once.

        Parameters
        ----------
        text : str
            What starts (``"writing the figures"``).
        """
        if not self.enabled:
            return
        self._end_cycles()
        self._write(str(text))

    def cycle(self, record) -> None:
        """Report one cycle: pass this method as ``steady_state(..., progress=...)``.

        Parameters
        ----------
        record : lcpfric.periodic.driver.CycleProgress
            The cycle's record (anything with ``cycle``, ``change``, ``tol``, ``max_cycles``).
        """
        if not self.enabled:
            return
        n, change, tol = int(record.cycle), float(record.change), float(record.tol)
        if self._use_bar is None:
            self._use_bar = _is_terminal(self.stream) and _tqdm() is not None
        if self._use_bar:
            self._advance_bar(n, change, tol)
            return
        if math.isfinite(change):
            text = f"cycle {n}: residual {change:.1e} (tol {tol:g})"
        else:
            text = f"cycle {n} of at most {int(record.max_cycles)} (tol {tol:g})"
        now = time.monotonic()
        if now - self._start >= self._delay and now - self._written_at >= self._interval:
            self._write(text)
            self._written_at, self._pending = now, None
            self._lines += 1
        else:
            self._pending = text

    def _advance_bar(self, n: int, change: float, tol: float) -> None:
        if self._bar is not None and n <= self._bar.n:  # a new run's cycles
            self._end_cycles()
        if self._bar is None:
            self._bar = _tqdm()(
                desc=self.what or "cycles",
                unit=" cycles",
                file=self.stream,
                dynamic_ncols=True,
                delay=self._delay,
            )
        residual = f"residual {change:.1e}" if math.isfinite(change) else "no residual yet"
        self._bar.set_postfix_str(f"{residual} (tol {tol:g})", refresh=False)
        self._bar.update(n - self._bar.n)

    def _end_cycles(self) -> None:
        """Close the cycles' bar, or write the last cycle line if earlier ones were written."""
        if self._bar is not None:
            bar, self._bar = self._bar, None
            bar.close()
        if self._pending is not None and self._lines:
            self._write(self._pending)
        self._pending, self._lines, self._written_at = None, 0, -math.inf

    def close(self) -> None:
        """End the report (the bar closed, the last cycle written); safe to call twice."""
        if self.enabled:
            self._end_cycles()

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

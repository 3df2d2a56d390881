"""One progress bar over a whole reproduction, with the time left.

A reproduction runs dozens of sweeps whose samples cost from milliseconds (a small grid solve)
to minutes (a threshold search at n = 64). The bar therefore counts work, not samples: each
saved sample advances it by its estimated cost (:func:`~.budget.estimate`, per sweep), each
finished study by its in-process work. The time left is the work left divided by the rate
measured so far, so a machine faster or slower than the budget's reference still gets an
honest estimate after the first few chunks.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

from tqdm.auto import tqdm

from .budget import Estimate

#: the bar's layout: no sample counts (its unit is estimated CPU seconds, meaningless to read)
BAR_FORMAT = "{desc}{percentage:3.0f}%|{bar}| {elapsed} elapsed, about {remaining} left"


class OverallProgress:
    """The bar of a reproduction; pass it as ``progress`` to the sweeps (it is called as
    ``progress(out, samples)`` after each saved chunk).

    Parameters
    ----------
    est : Estimate
        The work still to do (an estimate with ``out``: stored rows left out).
    enabled : bool
        Draw the bar (False: every call does nothing).
    """

    def __init__(self, est: Estimate, enabled: bool) -> None:
        rows: dict[str, int] = defaultdict(int)
        seconds: dict[str, float] = defaultdict(float)
        for s in est.sweeps:
            rows[s.name] += s.new_rows
            seconds[s.name] += s.cpu_seconds
        self.per_sample = {name: seconds[name] / rows[name] for name in rows if rows[name]}
        #: the cost of a sample of a sweep the estimate did not expect to run
        self.mean = sum(seconds.values()) / max(sum(rows.values()), 1)
        self.serial = dict(est.serial)
        #: estimated CPU seconds of the whole run and of what is done
        self.total, self.done = max(est.cpu_seconds, 1e-9), 0.0
        self.bar = tqdm(
            total=self.total,
            disable=not enabled,
            bar_format=BAR_FORMAT,
            dynamic_ncols=True,
            smoothing=0,  # the rate over the whole run so far: chunks differ too much in size
        )

    def _advance(self, seconds: float) -> None:
        step = min(seconds, self.total - self.done)  # an estimate too low stops at 100 %
        self.done += step
        self.bar.update(step)

    def __call__(self, out: Path, samples: int) -> None:
        self._advance(samples * self.per_sample.get(Path(out).name, self.mean))

    def study(self, i: int, n: int, name: str) -> None:
        """Say which study runs now."""
        self.bar.set_description(f"reproduce [{i}/{n}] {name}")

    def study_done(self, name: str) -> None:
        """Count a finished study's in-process work (its analysis)."""
        self._advance(self.serial.get(name, 0.0))

    def close(self) -> None:
        self.bar.close()

"""Helpers shared by the tests (pytest puts this folder on sys.path)."""

import threading

import numpy as np
import pytest


def diagonal(points):
    """The bounding-box diagonal of points (n, 3)."""
    return np.linalg.norm(points.max(axis=0) - points.min(axis=0))


def counts_alongside(work):
    """How far another Python thread counts while `work` runs in this one: next to nothing when
    `work` holds the GIL throughout."""
    count, done = [0], threading.Event()

    def counter():
        while not done.is_set():
            count[0] += 1

    thread = threading.Thread(target=counter)
    thread.start()
    try:
        work()
    finally:
        done.set()
        thread.join()
    return count[0]


def without_timings(report):
    """A JSON-like report without its "seconds" (which differ from run to run)."""
    if isinstance(report, dict):
        return {key: without_timings(value) for key, value in report.items() if key != "seconds"}
    if isinstance(report, list):
        return [without_timings(value) for value in report]
    return report


def assert_same_figures(ours, theirs, rel, where="report"):
    """Nested dicts and lists with the same keys, lengths, integers, flags and nulls, and floats
    equal up to `rel` (relative)."""
    assert type(ours) is type(theirs) or {type(ours), type(theirs)} <= {int, float}, where
    if isinstance(theirs, dict):
        assert list(ours) == list(theirs), where
        for key in theirs:
            assert_same_figures(ours[key], theirs[key], rel, f"{where}[{key!r}]")
    elif isinstance(theirs, list):
        assert len(ours) == len(theirs), where
        for index, (mine, other) in enumerate(zip(ours, theirs)):
            assert_same_figures(mine, other, rel, f"{where}[{index}]")
    elif isinstance(theirs, float):
        assert ours == pytest.approx(theirs, rel=rel), where
    else:
        assert ours == theirs, where

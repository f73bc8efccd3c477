"""Helpers shared by the tests (pytest puts this folder on sys.path)."""

import threading

import numpy as np


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

"""Threads: one Database queried from many Python threads at once gives the
answers of serial queries; builds, solves and batch queries release the
GIL; an interrupt during a build does not crash."""
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import geosep


def test_database_from_many_threads(sphere_db):
    n = sphere_db.n_vertices
    rng = np.random.default_rng(11)
    jobs = [rng.integers(0, n, (2, 20000)) for _ in range(8)]
    expected = [sphere_db.distance(x, y) for x, y in jobs]
    rows = np.arange(0, n, 5)
    expected_pairwise = sphere_db.pairwise(rows)
    failures = []
    barrier = threading.Barrier(len(jobs))

    fields = {int(x[1]): sphere_db.field(int(x[1])) for x, _ in jobs}

    def work(i):
        try:
            barrier.wait()
            x, y = jobs[i]
            for _ in range(5):
                if not np.array_equal(sphere_db.distance(x, y), expected[i]):
                    failures.append(("distance", i))
                if not np.array_equal(sphere_db.pairwise(rows), expected_pairwise):
                    failures.append(("pairwise", i))
                if sphere_db.distance(int(x[0]), int(y[0])) != expected[i][0]:
                    failures.append(("scalar", i))
                if not np.array_equal(sphere_db.field(int(x[1])), fields[int(x[1])]):
                    failures.append(("field", i))
        except Exception as e:  # an exception in a thread must fail the test
            failures.append(("exception", i, repr(e)))

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(jobs))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert failures == []


class Ticker:
    """A thread counting while the main thread is inside a C call. With the
    switch interval set very long, Python switches threads only where the
    GIL is released explicitly (time.sleep here, Py_BEGIN_ALLOW_THREADS in
    geosep): the count advances during the call only if the call releases
    the GIL."""

    def __enter__(self):
        self.count, self.stop = 0, False
        self.started = threading.Event()
        self.old = sys.getswitchinterval()
        sys.setswitchinterval(1000.0)
        self.thread = threading.Thread(target=self.run)
        self.thread.start()
        self.started.wait()
        return self

    def run(self):
        self.started.set()
        while not self.stop:
            self.count += 1
            time.sleep(0)  # releases the GIL

    def __exit__(self, *exc):
        self.stop = True
        self.thread.join()
        sys.setswitchinterval(self.old)


def advances(ticker, call, tries=200):
    """Whether the ticker counts during one of up to `tries` calls."""
    for _ in range(tries):
        before = ticker.count
        call()
        if ticker.count > before:
            return True
    return False


def test_gil_released():
    mesh = geosep.Mesh.generate("sphere:3")
    solver = geosep.Solver(mesh, "heat")
    x = np.random.default_rng(0).integers(0, mesh.n_vertices, (2, 200_000))
    with Ticker() as t:
        assert advances(t, lambda: geosep.Database.build(mesh, threads=1), tries=3), "the build held the GIL"
        db = geosep.Database.build(mesh)
        assert advances(t, lambda: solver.field([0, 5, 9])), "the solves held the GIL"
        assert advances(t, lambda: geosep.distance_field(mesh, 0)), "distance_field held the GIL"
        assert advances(t, lambda: db.distance(x[0], x[1])), "the batch query held the GIL"
        assert advances(t, lambda: db.pairwise(x[0, :300])), "pairwise held the GIL"
        assert advances(t, lambda: db.field(0)), "field held the GIL"
        assert advances(t, lambda: geosep.render(mesh, size=(320, 240))), "render held the GIL"


def test_interrupt_during_build():
    """SIGINT while a build runs: the build need not stop, but Python must
    raise KeyboardInterrupt afterwards (or finish), never crash."""
    script = textwrap.dedent(
        """
        import os, signal, threading, time
        import geosep
        mesh = geosep.Mesh.generate("sphere:3")
        # Python leaves SIGINT alone when it starts with SIGINT ignored (a
        # background job of a non-interactive shell): install the handler
        signal.signal(signal.SIGINT, signal.default_int_handler)
        threading.Timer(0.1, os.kill, (os.getpid(), signal.SIGINT)).start()
        try:
            db = geosep.Database.build(mesh, threads=1, progress=True)
            print("built", db.n_vertices)
            time.sleep(5)  # (a fast machine: the signal comes after the build)
        except KeyboardInterrupt:
            print("interrupted")
        """
    )
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split("\n")[-2] == "interrupted"

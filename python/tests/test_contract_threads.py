"""contract() in several Python threads at once: each run's stage and frame callbacks are called
on the thread that called contract(), and no run waits for another's work (each run has a task
arena of its own, src/core/arena_threads.hpp).

Before, the runs of one thread count shared an arena: while one run held its slot, another run's
preparation (its stage callbacks and its Ctrl-C check) ran on a TBB worker or on the first run's
thread. Then Ctrl-C stopped the wrong thread's contract(), and a thread-affine object (sqlite3)
used in a stage callback raised."""
import concurrent.futures
import threading

import numpy as np

import shellcontract as sc

# Short runs with the automatic regions: most of a run is its preparation, where the stage
# callbacks come, so that the threads' preparations overlap.
RUN = dict(frames=2, regions="auto")


def test_every_callback_runs_on_its_callers_thread(mesh_dir):
    # On the old shared arenas (one per thread count, for every run) stage callbacks ran on
    # another run's thread or on a TBB worker.
    V, F = sc.read_mesh(mesh_dir / "bumpy_sphere.off")
    foreign = []  # (thread, what, the caller's ident, the callback's ident)
    counts = {}
    statuses, errors = [], []
    lock = threading.Lock()

    def work(name, threads):
        me = threading.get_ident()

        def stage(what):
            with lock:
                counts[name] = counts.get(name, 0) + 1
                if threading.get_ident() != me:
                    foreign.append((name, what, me, threading.get_ident()))

        def callback(frame, vertices, metrics):
            if threading.get_ident() != me:
                with lock:
                    foreign.append((name, "frame %d" % frame, me, threading.get_ident()))

        try:
            for _ in range(4):
                statuses.append(sc.contract(V, F, stage=stage, callback=callback, threads=threads,
                                            **RUN).status)
        except BaseException as e:  # raised again by the main thread
            errors.append(e)

    workers = [threading.Thread(target=work, args=("run%d" % i, threads))
               for i, threads in enumerate([1, 1, 2, 2, 0])]
    for t in workers:
        t.start()
    work("main", 1)  # the main thread too: Ctrl-C's check belongs to its run alone
    for t in workers:
        t.join()
    if errors:
        raise errors[0]
    assert statuses == ["ok"] * 4 * (len(workers) + 1)
    assert foreign == []
    assert set(counts) == {"main"} | {"run%d" % i for i in range(len(workers))}


def test_a_stage_callback_may_wait_for_a_run_on_another_thread(mesh_dir):
    # The outer run holds its arena while its stage callback waits: the other thread's run must
    # not need that arena (a pool of arenas that made a run wait for a free one would hang here).
    V, F = sc.read_mesh(mesh_dir / "ico2.off")
    alone = sc.contract(V, F, frames=5, threads=1)
    got = []
    with concurrent.futures.ThreadPoolExecutor(1) as pool:
        def stage(what):
            if not got:
                got.append(pool.submit(sc.contract, V, F, frames=5, threads=1).result(timeout=120))

        r = sc.contract(V, F, stage=stage, threads=1, **RUN)
    assert r.status == "ok"
    assert len(got) == 1 and np.array_equal(got[0].vertices, alone.vertices)


def test_a_callback_may_run_contract_again_on_its_thread(mesh_dir):
    V, F = sc.read_mesh(mesh_dir / "ico2.off")
    for threads in (1, 2):
        alone = sc.contract(V, F, frames=5, threads=threads)
        got = []
        me = threading.get_ident()
        idents = set()

        def inner_stage(what):
            idents.add(threading.get_ident())

        def stage(what):
            idents.add(threading.get_ident())
            if not got:
                got.append(sc.contract(V, F, frames=5, threads=threads, stage=inner_stage))

        def callback(frame, vertices, metrics):
            if frame == 1:
                got.append(sc.contract(V, F, frames=5, threads=threads))

        r = sc.contract(V, F, stage=stage, callback=callback, threads=threads, **RUN)
        assert r.status == "ok"
        assert len(got) == 2
        for g in got:
            assert np.array_equal(g.vertices, alone.vertices)
        assert idents == {me}


def _run_in_child(path):
    v, f = sc.read_mesh(path)
    return sc.contract(v, f, **RUN).vertices


def test_a_process_forked_while_another_thread_runs_can_run(mesh_dir):
    """A worker pool forked (multiprocessing's default start method on Linux) while another
    thread of the parent is inside contract(): the child's own contract() ran in the arena the
    parent's run held, whose threads the child does not have, and hung for ever.
    With an arena per run the child's run takes one of its own."""
    import multiprocessing
    path = mesh_dir / "bumpy_sphere.off"
    v, f = sc.read_mesh(path)
    expected = sc.contract(v, f, **RUN).vertices
    stop = threading.Event()

    def busy():
        while not stop.is_set():
            sc.contract(v, f, **RUN)

    worker = threading.Thread(target=busy)
    worker.start()
    try:
        for _ in range(4):
            with multiprocessing.get_context("fork").Pool(1) as pool:
                got = pool.apply_async(_run_in_child, (path,)).get(timeout=120)
            np.testing.assert_array_equal(got, expected)
    finally:
        stop.set()
        worker.join()

"""Reliability of sweeps (issue 18): one writer per directory, kills, failures, checksums, sizes.

Process-level failures (concurrent sweeps, kills, orphaned workers, a dying Dask scheduler) are
tested on real subprocesses of the command line.
"""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pandas as pd
import pytest

import tensegrity_rigidity.ensemble.sweep as sweep_mod
from tensegrity_rigidity.cli.main import main
from tensegrity_rigidity.ensemble.store import ResultStore
from tensegrity_rigidity.ensemble.sweep import load_results, run_sweep
from tensegrity_rigidity.errors import InputError, SpecError

from ..processes import unprivileged

SMALL = """
n = 5
p_r = [0.55, 0.7]
p_t = [0.0, 0.25]
phi = ["dilation", "compression"]
samples = 8
seed = 3
[output]
chunk_size = 4
"""
#: a few seconds of work: long enough to be caught mid-run, short enough to finish
LONG = SMALL.replace("n = 5", "n = 8").replace("samples = 8", "samples = 40")
#: minutes of work: only ever interrupted
ENDLESS = SMALL.replace("n = 5", "n = 8").replace("samples = 8", "samples = 4000")


def _write(tmp_path, text, name="spec.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def _cmd(spec, out, workers=2):
    return [
        sys.executable,
        "-m",
        "tensegrity_rigidity",
        "sweep",
        str(spec),
        "--out",
        str(out),
        "--workers",
        str(workers),
        "--no-progress",
    ]


def _wait_for_parts(out: Path, count: int, proc=None, timeout: float = 60) -> None:
    deadline = time.time() + timeout
    while time.time() < deadline and len(list(out.glob("part-*.parquet"))) < count:
        if proc is not None and proc.poll() is not None:
            break
        time.sleep(0.05)


def _frame(out, spec=None):
    return load_results(out, spec).drop(columns=["solve_seconds"]).reset_index(drop=True)


def _fresh(spec, out):
    run_sweep(spec, out, executor="serial", progress=False)
    return _frame(out)


def _children(pid: int) -> list[int]:
    """Pids of the direct children of a process (Linux /proc)."""
    out = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                out.append(int(entry.name))
    return out


def _alive(pid: int) -> bool:
    try:
        state = (Path("/proc") / str(pid) / "stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


linux_only = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc")


# --------------------------------------------------------------------------- one writer


def _check_one_writer(out: Path) -> None:
    """Every listed part is whole and all rows belong to one sweep."""
    rows = load_results(out, all_rows=True)
    assert len(rows) and rows["seed"].nunique() == 1  # no foreign rows
    assert rows.duplicated(["point_key", "sample", "theta"]).sum() == 0
    assert len(rows) == len(ResultStore(out).manifest()) * 4


def test_two_sweeps_started_together_one_writes_the_other_is_refused(tmp_path):
    a = _write(tmp_path, ENDLESS, "a.toml")
    b = _write(tmp_path, ENDLESS.replace("seed = 3", "seed = 4"), "b.toml")
    out = tmp_path / "shared"
    procs = [subprocess.Popen(_cmd(s, out, 1), stderr=subprocess.PIPE, text=True) for s in (a, b)]
    refused = None
    deadline = time.time() + 60
    while refused is None and time.time() < deadline:
        refused = next((p for p in procs if p.poll() is not None), None)
        time.sleep(0.05)
    winner = next(p for p in procs if p is not refused)
    _wait_for_parts(out, 2, winner)
    winner.send_signal(
        signal.SIGTERM
    )  # (SIGINT may be ignored when the tests run in the background)
    _, winner_err = winner.communicate(timeout=60)
    assert refused is not None, "neither sweep was refused"
    err = refused.stderr.read().strip()
    assert refused.returncode == 2 and len(err.splitlines()) == 1, err
    assert "being written by another sweep" in err and "pid" in err
    assert winner.returncode == 143 and "Traceback" not in winner_err, winner_err
    _check_one_writer(out)


def test_refused_sweep_touches_nothing_of_the_running_one(tmp_path):
    """A second sweep (of another spec, or the same) into a busy directory breaks nothing."""
    spec = _write(tmp_path, ENDLESS)
    out = tmp_path / "busy"
    running = subprocess.Popen(_cmd(spec, out, 1), stderr=subprocess.PIPE, text=True)
    _wait_for_parts(out, 2, running)
    other = _write(tmp_path, ENDLESS.replace("seed = 3", "seed = 9"), "other.toml")
    for s in (other, spec):
        second = subprocess.run(_cmd(s, out, 1), capture_output=True, text=True, timeout=60)
        assert second.returncode == 2 and "being written by another sweep" in second.stderr
        assert running.poll() is None, "the running sweep died"
    info = subprocess.run(
        [sys.executable, "-m", "tensegrity_rigidity", "info", str(out)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert f"being written now by pid {running.pid}" in info.stdout, info.stdout + info.stderr
    _wait_for_parts(out, len(list(out.glob("part-*.parquet"))) + 2, running)
    running.send_signal(signal.SIGTERM)
    _, err = running.communicate(timeout=60)
    assert running.returncode == 143 and "Traceback" not in err, err
    _check_one_writer(out)


def test_prepare_checks_the_spec_before_deleting_anything(tmp_path):
    """Temporary files of a live writer survive a refused sweep and an accepted one."""
    spec = _write(tmp_path, SMALL)
    out = tmp_path / "o"
    run_sweep(spec, out, executor="serial", progress=False)
    live = out / f".part-x.parquet.{os.getppid()}.tmp"  # a process that is alive: our parent
    dead = out / ".part-y.parquet.999999999.tmp"
    live.write_bytes(b"in progress")
    dead.write_bytes(b"left by a killed run")
    other = _write(tmp_path, SMALL + "[solver]\nviolation_tol = 1e-8\n", "other.toml")
    with pytest.raises(SpecError, match="different sweep"):
        run_sweep(other, out, executor="serial", progress=False)
    assert live.exists() and dead.exists()
    run_sweep(spec, out, executor="serial", progress=False)
    assert live.exists() and not dead.exists()


def test_rows_of_another_revision_are_not_resumed(tmp_path):
    """A directory whose rows were written under another ROWS_REVISION (here: by a version
    before the record existed, revision 1) is refused, not resumed into a mix of both rules;
    a directory of the current revision resumes."""
    import json

    from tensegrity_rigidity.ensemble.store import ROWS_REVISION

    spec = _write(tmp_path, SMALL)
    out = tmp_path / "o"
    run_sweep(spec, out, executor="serial", progress=False)
    meta = out / "_spec.json"
    record = json.loads(meta.read_text())
    assert record["rows_revision"] == ROWS_REVISION["grid"]
    run_sweep(spec, out, executor="serial", progress=False)  # same revision: resumes
    del record["rows_revision"]
    meta.write_text(json.dumps(record))
    parts = sorted(p.name for p in out.glob("part-*"))
    with pytest.raises(SpecError, match="rows of revision 1"):
        run_sweep(spec, out, executor="serial", progress=False)
    assert sorted(p.name for p in out.glob("part-*")) == parts  # nothing deleted or added


def test_threshold_rows_keep_their_revision_when_grid_rows_change(tmp_path):
    """Each mode has its own rows revision. Threshold rows hold only verdicts, so they stayed
    at revision 2 while grid rows went to revisions 3 to 7 (the relaxation's longer interior
    point, its smaller shift, the projection's reduced system, its active set and its stop at
    the first certified iterate); both went up by one when purification started stopping
    early (its certificates, hence the verdicts of probes near a threshold, can differ); grid
    rows alone went to 9 when the projection stopped refining its predictor; both went up by
    one again when purification began counting round-off work as none (and balancing
    became selective); grid rows alone went to 11 when the relaxed tensions' support optimum
    began certifying energies purification left open, to 12 when the affine energy
    stopped depending on the BLAS thread count, to 13 when stalled projections had their
    multipliers refined in extended precision, and to 14 when rows began to carry a lower
    bound on the nonaffinity where it is not certified. Packing rows (soft packings and
    their jamming tests) started at 1. A directory
    recorded at the threshold revision resumes as a threshold sweep and is refused
    as a grid sweep."""
    import json

    from tensegrity_rigidity.ensemble.store import ROWS_REVISION

    assert ROWS_REVISION == {"grid": 14, "threshold": 4, "packing": 1}
    threshold = SMALL.replace("p_r = [0.55, 0.7]\n", "").replace(
        "[output]", '[threshold]\npath = "p_r"\n[output]'
    )
    for text, name, refused in ((threshold, "t", False), (SMALL, "g", True)):
        spec = _write(tmp_path, text, f"{name}.toml")
        out = tmp_path / name
        run_sweep(spec, out, executor="serial", progress=False)
        meta = out / "_spec.json"
        record = json.loads(meta.read_text())
        record["rows_revision"] = ROWS_REVISION["threshold"]
        meta.write_text(json.dumps(record))
        if refused:
            with pytest.raises(SpecError, match="rows of revision 4"):
                run_sweep(spec, out, executor="serial", progress=False)
        else:
            run_sweep(spec, out, executor="serial", progress=False)


def test_store_refuses_to_write_without_the_lock(tmp_path):
    from tensegrity_rigidity.ensemble.spec import load_spec

    store = ResultStore(tmp_path / "x")
    with pytest.raises(RuntimeError, match="lock"):
        store.prepare(load_spec(_write(tmp_path, SMALL)))


# --------------------------------------------------------------------------- kills


@linux_only
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_killing_the_main_process_leaves_no_workers(tmp_path, sig):
    spec = _write(tmp_path, LONG)
    out = tmp_path / "k"
    proc = subprocess.Popen(_cmd(spec, out, 2), stderr=subprocess.PIPE, text=True)
    _wait_for_parts(out, 1, proc)
    workers = _children(proc.pid)
    assert len(workers) == 2, workers
    proc.send_signal(sig)  # the main process only, not its process group
    _, err = proc.communicate(timeout=60)
    deadline = time.time() + 10
    while time.time() < deadline and any(_alive(w) for w in workers):
        time.sleep(0.1)
    orphans = [w for w in workers if _alive(w)]
    for w in orphans:  # leave no process behind, even when the test fails
        os.kill(w, signal.SIGKILL)
    assert not orphans, "orphaned pool workers"
    if sig == signal.SIGTERM:
        assert proc.returncode == 143 and "Traceback" not in err
        assert err.strip().startswith("terminated:") and "resume" in err
        assert not list(out.glob(".*.tmp"))


def _descendants(pid: int) -> list[int]:
    """Pids of every descendant of a process (Linux /proc)."""
    out, todo = [], [pid]
    while todo:
        for child in _children(todo.pop()):
            out.append(child)
            todo.append(child)
    return out


def _max_children(proc) -> int:
    """The most child processes ``proc`` had at once until it ended (polled)."""
    most = 0
    while proc.poll() is None:
        most = max(most, len(_children(proc.pid)))
        time.sleep(0.02)
    return most


#: one chunk of two samples at n = 4
ONE_CHUNK = """
n = 4
p_r = 0.6
samples = 2
"""


@linux_only
def test_a_worker_count_above_the_cores_is_capped_and_never_exceeds_the_chunks(tmp_path):
    """--workers 64 forked 64 processes for a sweep of one chunk (and 100000 exhausted the
    machine's memory): now a one-line warning, the usable cores at most, and a sweep of one
    chunk runs in the main process."""
    from tensegrity_rigidity.ensemble.executors import usable_cores

    spec = _write(tmp_path, ONE_CHUNK)
    proc = subprocess.Popen(
        _cmd(spec, tmp_path / "one", 64), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert _max_children(proc) == 0
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 0, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("warning: 64 worker processes asked for")
    three = _write(
        tmp_path,
        SMALL.replace("samples = 8", "samples = 4")
        .replace("p_r = [0.55, 0.7]", "p_r = 0.55")
        .replace('phi = ["dilation", "compression"]', 'phi = "dilation"'),
        "three.toml",
    )
    proc = subprocess.Popen(_cmd(three, tmp_path / "three", 64), stderr=subprocess.PIPE, text=True)
    most = _max_children(proc)
    proc.communicate(timeout=60)
    assert proc.returncode == 0
    assert 1 <= most <= min(usable_cores(), 2)  # two chunks: p_t = 0 and 0.25


def _wait_for_main(proc, timeout: float = 30) -> None:
    """Wait until the command line's ``main()`` has blocked SIGINT and SIGTERM (its first
    line): before it, Python itself is starting and handles signals its own way."""
    wanted = (1 << (signal.SIGINT - 1)) | (1 << (signal.SIGTERM - 1))
    deadline = time.time() + timeout
    while time.time() < deadline and proc.poll() is None:
        try:
            status = Path(f"/proc/{proc.pid}/status").read_text()
        except OSError:
            break
        blocked = int(status.split("SigBlk:")[1].split()[0], 16)
        if blocked & wanted == wanted:
            return
        time.sleep(0.002)


@linux_only
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_at_any_moment_of_the_start_up_ends_in_one_line(tmp_path, sig):
    """Ctrl-C during the imports printed a traceback (KeyboardInterrupt, or a SystemError from
    a C extension's initialisation); now, from the first line of ``main()`` on, one line and
    status 130 / 143 at every delay, and no process left behind."""
    spec = _write(tmp_path, LONG)
    status = 130 if sig == signal.SIGINT else 143
    for i, delay in enumerate((0.0, 0.05, 0.2, 0.5, 1.0, 1.5)):
        proc = subprocess.Popen(
            _cmd(spec, tmp_path / f"s{i}", 2),
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )
        _wait_for_main(proc)
        time.sleep(delay)
        family = _descendants(proc.pid)
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=60)
        lines = err.strip().splitlines()
        assert proc.returncode == status, (delay, err)
        assert len(lines) == 1 and "Traceback" not in err, (delay, err)
        assert lines[0].startswith(("interrupted", "terminated")), (delay, err)
        deadline = time.time() + 10
        while time.time() < deadline and any(_alive(w) for w in family):
            time.sleep(0.1)
        assert not [w for w in family if _alive(w)], delay


DASK_SWEEP = """
import sys
from distributed import Client, LocalCluster
from tensegrity_rigidity import run_sweep
if __name__ == "__main__":
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None)
    run_sweep(sys.argv[1], sys.argv[2], executor=Client(cluster), progress=False)
"""


@linux_only
def test_killing_a_sweep_on_a_local_dask_cluster_leaves_no_workers(tmp_path):
    pytest.importorskip("distributed")
    spec = _write(tmp_path, LONG)
    script = tmp_path / "dask_sweep.py"
    script.write_text(DASK_SWEEP)
    out = tmp_path / "dask"
    proc = subprocess.Popen(
        [sys.executable, str(script), str(spec), str(out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    _wait_for_parts(out, 1, proc, timeout=120)
    family = _descendants(proc.pid)
    assert len(family) >= 2, family  # the cluster's worker processes
    proc.kill()
    proc.wait()
    deadline = time.time() + 20
    while time.time() < deadline and any(_alive(w) for w in family):
        time.sleep(0.2)
    orphans = [w for w in family if _alive(w)]
    for w in orphans:
        os.kill(w, signal.SIGKILL)
    assert not orphans, "orphaned Dask worker processes"


@linux_only
def test_a_killed_worker_saves_finished_chunks_and_ends_in_one_line(tmp_path):
    spec = _write(tmp_path, LONG)
    out = tmp_path / "w"
    proc = subprocess.Popen(_cmd(spec, out, 2), stderr=subprocess.PIPE, text=True)
    _wait_for_parts(out, 2, proc)
    os.kill(_children(proc.pid)[0], signal.SIGKILL)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 1, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "a worker process died" in err and "run the same command again" in err
    assert list(out.glob("part-*.parquet"))
    subprocess.run(_cmd(spec, out, 2), check=True, capture_output=True)
    from tensegrity_rigidity.ensemble.spec import load_spec

    pd.testing.assert_frame_equal(_frame(out), _fresh(load_spec(spec), tmp_path / "fresh"))


def test_one_failing_chunk_keeps_every_other_chunk(tmp_path, capsys, monkeypatch):
    spec = _write(tmp_path, SMALL)
    out = tmp_path / "f"
    real = sweep_mod.run_chunk

    def flaky(spec, point, samples):
        if point.p_r == 0.7 and point.p_t == 0.25 and point.phi == 0.0 and samples[0] == 5:
            raise MemoryError("cannot allocate 1.2 TiB")
        return real(spec, point, samples)

    monkeypatch.setattr(sweep_mod, "run_chunk", flaky)
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("error: 1 of 16 chunks failed"), err
    assert "MemoryError: cannot allocate" in err and "p_r = 0.7" in err and "resume" in err
    assert len(load_results(out)) == 2 * 2 * 2 * 8 - 4  # every other chunk is saved
    monkeypatch.setattr(sweep_mod, "run_chunk", real)
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    from tensegrity_rigidity.ensemble.spec import load_spec

    pd.testing.assert_frame_equal(_frame(out), _fresh(load_spec(spec), tmp_path / "fresh"))


def test_chunks_the_solver_refuses_do_not_advise_a_resume(tmp_path, capsys, monkeypatch):
    """A verdict is a function of its input: a chunk whose input the solver refuses fails again
    on every resume, so the message says to change the spec instead."""
    spec = _write(tmp_path, SMALL)

    def refused(spec, point, samples):
        raise InputError("the largest affine extension is 1.0e+200, outside [1e-150, 1e+150]")

    monkeypatch.setattr(sweep_mod, "run_chunk", refused)
    code = main(["sweep", str(spec), "--out", str(tmp_path / "r"), "--workers", "1"])
    err = capsys.readouterr().err.strip()
    assert code == 1 and len(err.splitlines()) == 1, err
    assert "change the spec" in err and "run the same command again to resume" not in err


def test_sigterm_swallowed_inside_a_chunk_still_ends_the_sweep(tmp_path, capsys, monkeypatch):
    """A C extension calling back into Python can swallow the handler's exception (1 of 41
    SIGTERMs of a serial sweep ran on to the end); the recorded request ends it after the chunk."""
    spec = _write(tmp_path, SMALL)
    out = tmp_path / "t"
    real = sweep_mod.run_chunk
    calls = []

    def swallowing(spec, point, samples):
        calls.append(samples[0])
        if len(calls) == 2:
            try:  # the handler the command line installed, run where its exception is lost
                signal.getsignal(signal.SIGTERM)(signal.SIGTERM, None)
            except KeyboardInterrupt:
                pass
        return real(spec, point, samples)

    monkeypatch.setattr(sweep_mod, "run_chunk", swallowing)
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 143
    assert len(calls) == 2 and len(load_results(out)) == 2 * 4  # both chunks saved, no more run
    assert "terminated" in capsys.readouterr().err
    assert main(["info", str(out)]) == 0  # a later command in the same process is not ended


def test_full_disk_saves_what_it_can_and_ends_in_one_line(tmp_path, capsys, monkeypatch):
    spec = _write(tmp_path, SMALL)
    out = tmp_path / "full"
    real = ResultStore._atomic_write
    calls = {"parts": 0}

    def filling(path, data):
        if path.name.startswith("part-"):
            calls["parts"] += 1
            if calls["parts"] > 3:
                tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
                tmp.write_bytes(data[:10])  # a partial write, then the disk is full
                tmp.unlink()
                raise OSError(errno.ENOSPC, "No space left on device")
        return real(path, data)

    monkeypatch.setattr(ResultStore, "_atomic_write", staticmethod(filling))
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "No space left on device" in err and "resume" in err
    assert len(load_results(out)) == 3 * 4 and not list(out.glob(".*.tmp"))
    monkeypatch.setattr(ResultStore, "_atomic_write", staticmethod(real))
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0


# --------------------------------------------------------------------------- Dask


def _dask_cli(*args) -> list[str]:
    return [sys.executable, "-m", "distributed.cli.dask_" + args[0], *args[1:]]


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def scheduler():
    """A Dask scheduler process (killed at the end); yields (address, process)."""
    pytest.importorskip("distributed")
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    proc = subprocess.Popen(
        _dask_cli("scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    import socket

    deadline = time.time() + 60
    while time.time() < deadline:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            break
        except OSError:
            time.sleep(0.2)
    yield address, proc
    proc.kill()
    proc.wait()


def test_scheduler_without_workers_fails_after_the_stated_wait(tmp_path, scheduler):
    address, _ = scheduler
    spec = _write(tmp_path, SMALL)
    out = tmp_path / "never"
    cmd = _cmd(spec, out)[:-3] + ["--scheduler", address, "--wait-workers", "2"]
    start = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    took = time.time() - start
    err = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and 2 <= took < 30, (took, err)
    assert err[0] == (
        f"warning: the Dask scheduler at {address} has no workers; waiting up to 2 s for one"
    )
    assert len(err) == 2 and err[1].startswith("error: no worker joined") and "within 2 s" in err[1]
    assert not out.exists()


def test_dead_scheduler_saves_finished_chunks_and_ends_in_one_line(tmp_path, scheduler):
    address, sched = scheduler
    worker = subprocess.Popen(
        _dask_cli("worker", address, "--nthreads", "1", "--no-dashboard"),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        spec = _write(tmp_path, LONG)
        out = tmp_path / "d"
        cmd = _cmd(spec, out)[:-3] + ["--scheduler", address, "--no-progress"]
        proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)
        _wait_for_parts(out, 2, proc, timeout=120)
        sched.kill()
        _, err = proc.communicate(timeout=120)
    finally:
        worker.kill()
        worker.wait()
    assert proc.returncode == 1, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert "the Dask scheduler or its workers went away" in err and "resume" in err
    assert len(list(out.glob("part-*.parquet"))) >= 2
    subprocess.run(_cmd(spec, out, 2), check=True, capture_output=True)
    from tensegrity_rigidity.ensemble.spec import load_spec

    pd.testing.assert_frame_equal(_frame(out), _fresh(load_spec(spec), tmp_path / "fresh"))


# --------------------------------------------------------------------------- checksums


def test_flipped_byte_inside_a_part_is_detected_and_recomputed(tmp_path, capsys):
    spec = _write(tmp_path, SMALL)
    out = tmp_path / "c"
    run_sweep(spec, out, executor="serial", progress=False)
    part = sorted(out.glob("part-*.parquet"))[3]
    data = bytearray(part.read_bytes())
    for i in range(4):  # four bytes in the middle: the footer still parses
        data[len(data) // 2 + i] ^= 0xFF
    part.write_bytes(bytes(data))
    with pytest.raises(InputError, match="damaged"):
        load_results(out)  # a reader never returns rows of a damaged part
    code = main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 0 and len(err) == 1
    assert err[0].startswith("warning: ") and "checksum mismatch" in err[0] and part.name in err[0]
    from tensegrity_rigidity.ensemble.spec import load_spec

    pd.testing.assert_frame_equal(_frame(out), _fresh(load_spec(spec), tmp_path / "fresh"))


def test_deleted_part_is_recomputed_with_a_warning(tmp_path, capsys):
    spec = _write(tmp_path, SMALL)
    out = tmp_path / "d"
    run_sweep(spec, out, executor="serial", progress=False)
    part = sorted(out.glob("part-*.parquet"))[2]
    part.unlink()
    code = main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 0 and len(err) == 1, err
    assert err[0].startswith("warning: ") and "missing" in err[0] and part.name in err[0]
    assert "recomputed" in err[0]
    from tensegrity_rigidity.ensemble.spec import load_spec

    pd.testing.assert_frame_equal(_frame(out), _fresh(load_spec(spec), tmp_path / "fresh"))


def test_part_missing_from_the_manifest_is_recomputed(tmp_path):
    """A kill between a part's rename and its manifest line leaves an unlisted part: it is not
    trusted (its rows are recomputed) and removed, so the dataset never holds a row twice."""
    spec = _write(tmp_path, SMALL)
    out = tmp_path / "m"
    run_sweep(spec, out, executor="serial", progress=False)
    lines = (out / "_manifest.jsonl").read_text().splitlines()
    (out / "_manifest.jsonl").write_text("\n".join(lines[:-1]) + '\n{"part": "torn')
    rechunked = _write(tmp_path, SMALL.replace("chunk_size = 4", "chunk_size = 3"), "r.toml")
    rep = run_sweep(rechunked, out, executor="serial", progress=False)
    assert rep.samples_run == 4 and rep.chunks_run == 2
    everything = pd.read_parquet(out)
    assert len(everything) == 2 * 2 * 2 * 8
    assert not everything.duplicated(["point_key", "sample", "theta"]).any()


def test_a_manifest_line_that_is_not_utf8_is_skipped_as_a_torn_one(tmp_path):
    """A byte that is not UTF-8 in the manifest raised UnicodeDecodeError from info,
    load_results and a resumed sweep; it is damage, skipped like a torn line."""
    spec = _write(tmp_path, SMALL)
    out = tmp_path / "u"
    run_sweep(spec, out, executor="serial", progress=False)
    with open(out / "_manifest.jsonl", "ab") as f:
        f.write(b"\xff{\n")
    assert len(load_results(out)) == 2 * 2 * 2 * 8
    assert run_sweep(spec, out, executor="serial", progress=False).samples_run == 0


def test_a_part_that_matches_its_checksum_but_is_no_results_table_is_refused_by_name(tmp_path):
    """Only a forged manifest gets there: a pyarrow traceback became one line naming it."""
    import hashlib
    import json

    spec = _write(tmp_path, SMALL)
    out = tmp_path / "p"
    run_sweep(spec, out, executor="serial", progress=False)
    lines = (out / "_manifest.jsonl").read_text().splitlines()
    entry = json.loads(lines[0])
    garbage = b"not parquet at all"
    (out / entry["part"]).write_bytes(garbage)
    entry |= {"bytes": len(garbage), "sha256": hashlib.sha256(garbage).hexdigest()}
    (out / "_manifest.jsonl").write_text("\n".join([json.dumps(entry), *lines[1:]]) + "\n")
    with pytest.raises(InputError, match=f"{entry['part']}: not a results part"):
        load_results(out)


# --------------------------------------------------------------------------- size guards


def _limit_memory():  # what a guard failed to refuse must not take the machine down
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))


HALF = [i / 2000 for i in range(1000)]  # p_r + p_t stays below 1
WHOLE = [i / 1000 for i in range(1000)]


@pytest.mark.parametrize(
    "text,needle",
    [
        ("n = 5\np_r = 0.5\nsamples = 1000000000\n", "1,000,000,000 samples"),
        (f"n = 5\np_r = {HALF}\np_t = {HALF}\nf_c = {WHOLE}\nsamples = 1\n", "1,000,000,000 grid"),
        ("n = 100000\np_r = 0.5\nsamples = 1\n", "n = 100000 needs about"),
        ("n = [5, 100000]\np_r = 0.5\nsamples = 1\n", "n = 100000 needs about"),
    ],
)
def test_what_cannot_fit_is_refused_before_starting(tmp_path, text, needle):
    spec = _write(tmp_path, text)
    out = tmp_path / "never"
    start = time.time()
    proc = subprocess.run(
        _cmd(spec, out, 1), capture_output=True, text=True, timeout=120, preexec_fn=_limit_memory
    )
    err = proc.stderr.strip()
    assert proc.returncode == 2, err
    assert len(err.splitlines()) == 1 and needle in err and "this machine has" in err, err
    assert time.time() - start < 60 and not out.exists()


def test_disk_too_small_for_the_missing_rows_is_refused(tmp_path, monkeypatch):
    import shutil

    spec = _write(tmp_path, SMALL)
    out = tmp_path / "d"
    run_sweep(spec, out, executor="serial", progress=False)  # 64 rows done
    grown = _write(tmp_path, SMALL.replace("samples = 8", "samples = 12"), "g.toml")
    real = shutil.disk_usage
    monkeypatch.setattr(shutil, "disk_usage", lambda p: real(p)._replace(free=50_000))
    with pytest.raises(SpecError, match=r"32 missing rows need about 120.3 KiB of disk"):
        run_sweep(grown, out, executor="serial", progress=False)
    monkeypatch.setattr(shutil, "disk_usage", lambda p: real(p)._replace(free=300_000))
    assert run_sweep(grown, out, executor="serial", progress=False).samples_run == 32


def test_out_that_is_a_file_or_empty_is_one_line(tmp_path, capsys):
    spec = _write(tmp_path, SMALL)
    afile = tmp_path / "afile"
    afile.write_text("x")
    for out, needle in ((str(afile), "is a file"), ("", "--out is empty")):
        assert main(["sweep", str(spec), "--out", out, "--workers", "1"]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and needle in err, err
    assert afile.read_text() == "x" and not list(Path.cwd().glob("part-*"))


@pytest.mark.skipif(not hasattr(os, "geteuid"), reason="POSIX permissions")
def test_read_only_out_is_one_line(tmp_path):
    spec = _write(tmp_path, SMALL)
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        for out in (ro, ro / "sub"):
            cmd = unprivileged(_cmd(spec, out, 1))
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
            assert proc.returncode == 2, proc.stderr
            err = proc.stderr.strip()
            assert len(err.splitlines()) == 1 and err.startswith("error: "), err
            assert "not writable" in err or "cannot create" in err, err
        assert list(ro.iterdir()) == []
    finally:
        ro.chmod(0o755)


#: values of p_r in the large grid: every task used to pickle the whole spec (here 90 kB,
#: more than a pipe holds), so a killed pool left its queue feeder blocked for ever
LARGE_GRID = 10_000


@linux_only
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_large_sweep_exits_on_a_signal_to_its_process_group(tmp_path, sig):
    """A batch scheduler's SIGTERM (or a terminal's Ctrl-C) reaches the whole process group:
    with a large grid the sweep printed "terminated ... saved", then an InvalidStateError
    traceback from the process pool, and never exited. Now: one line, 143 / 130, every
    finished chunk kept, no process left behind."""
    values = ", ".join(f"{0.5 + 0.2 * i / LARGE_GRID:.6f}" for i in range(LARGE_GRID))
    spec = _write(tmp_path, f"n = 4\np_r = [{values}]\nsamples = 1\n")
    out = tmp_path / "large"
    proc = subprocess.Popen(
        _cmd(spec, out, 2),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        _wait_for_parts(out, 2, proc, timeout=120)
        family = _descendants(proc.pid)
        os.killpg(proc.pid, sig)
        _, err = proc.communicate(timeout=60)  # it never exited
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
    assert proc.returncode == (143 if sig == signal.SIGTERM else 130), err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err and "Error" not in err, err
    word = "terminated" if sig == signal.SIGTERM else "interrupted"
    assert lines[0].startswith(f"{word}: ") and "saved" in lines[0], err
    saved = int(lines[0].split(": ")[1].split()[0])
    assert saved >= 2 and len(load_results(out)) == saved
    deadline = time.time() + 10
    while time.time() < deadline and any(_alive(w) for w in family):
        time.sleep(0.1)
    assert not [w for w in family if _alive(w)]


def test_a_task_carries_its_grid_point_not_the_grid():
    """What a task pickles does not grow with the grid."""
    import pickle

    from tensegrity_rigidity import parse_spec

    small = parse_spec({"n": 4, "p_r": [0.5, 0.6], "samples": 2})
    large = parse_spec({"n": 4, "p_r": [0.5 + i * 1e-6 for i in range(LARGE_GRID)], "samples": 2})
    point = large.points()[17]
    task = pickle.dumps((large.at(point), point, [1, 2]))
    assert len(task) <= len(pickle.dumps((small, point, [1, 2]))) + 200
    assert large.at(point).point_key(point) == large.point_key(point)
    assert large.at(point).points() == [point]


@linux_only
def test_aborting_a_local_pool_after_a_stop_raises_nothing_in_its_threads(monkeypatch):
    """A sweep that stops cancels its futures, then aborts the pool (its workers killed, or
    already dead from a group SIGTERM). Cancelled futures still queued in the executor made its
    own thread fail with InvalidStateError when it marked them broken, before it closed its
    queues: a traceback, then an interpreter that waited for those queues at exit."""
    import threading

    from tensegrity_rigidity.ensemble.executors import _LocalPool

    errors = []
    monkeypatch.setattr(threading, "excepthook", lambda args: errors.append(args.exc_value))
    pool = _LocalPool(2)
    pool.start(64)
    futures = [pool.submit(time.sleep, 5) for _ in range(64)]
    time.sleep(0.2)  # two running, the rest queued
    pool.cancel(futures)
    executor = pool._executor
    for proc in list(executor._processes.values()):  # the group SIGTERM
        os.kill(proc.pid, signal.SIGTERM)
    executor._executor_manager_thread.join(timeout=30)  # it saw the workers die
    pool.close(abort=True)
    assert errors == []
    assert all(f.done() for f in futures)


@pytest.mark.parametrize(
    "data",
    [
        {"n": [4, 8], "p_r": [0.5, 0.7], "p_t": [0.0, 0.2], "phi": ["shear", 1.3], "samples": 3},
        {"n": 4, "p_t": 0.0, "samples": 3, "threshold": {"path": "p_r", "method": "pebble"}},
        {"n": 4, "p_t": 0.1, "samples": 3, "threshold": {"path": "total"}},
        {"n": 3, "p_r": 0.6, "samples": 2, "lattice": {"kind": "fcc"}, "solver": {"max_iter": 9}},
    ],
)
def test_point_keys_are_still_the_digest_of_the_settings_and_the_point(data):
    """Point keys encode the settings once per spec now; every stored row's key must stay
    what the whole record's JSON digest was (the committed reports are keyed by it)."""
    import hashlib
    import json
    from dataclasses import asdict

    from tensegrity_rigidity import parse_spec

    spec = parse_spec(data)
    for point in spec.points():
        # the record as it was before points had a packing fraction (packing sweeps only)
        p = {k: v for k, v in asdict(point).items() if k != "fraction"}
        if spec.mode == "threshold":
            p["p_r"] = None
        record = {"settings": spec.settings(), "point": p}
        want = hashlib.sha256(json.dumps(record, sort_keys=True).encode()).hexdigest()[:24]
        assert spec.point_key(point) == want

#!/usr/bin/env python3
"""Benchmark of a map series (issue 30): 8 synthetic sheets through actinia
with 1 and with 2 jobs at a time, against 8 sequential local runs.

The sheets are 200 m x 200 m of one 400 m x 800 m synthetic town (seed 1),
cut by testsuite/synthetic_sheets.py; each run is tools/histo_series.py on
them (the merge included). Prints, per way of running, the wall time, the
sheets per hour and the peak memory: the largest sum of the resident memory
(RSS) of every process of the run, sampled every 0.2 s: the driver and the
GRASS sessions it starts (local), plus actinia's and Redis's processes
(actinia; started by tools/actinia/service.sh on free ports, stopped at the
end). With queue_type=local, actinia starts each job it accepts at once in
a process of its own: "1 and 2 workers" are the driver's --jobs 1 and 2.
Last, the set-up of several machines on loopback: queue_type=redis with
two queues, two REST servers (the driver sends to each in turn) and two
queue workers, all sharing one Redis and one GRASS database (service.sh
start with QUEUES=2, server, worker), --jobs 2.

    python3 testsuite/benchmarks/bench_series.py   (also through run_all.sh)
"""

import os
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
import synthetic_map  # noqa: E402
import synthetic_sheets  # noqa: E402

DIST = os.environ.get("HISTO_DIST", os.path.join(ROOT, "dist"))
SHEETS = [(c, r) for r in range(4) for c in range(2)]


def sessions_rss(sids):
    """Total RSS (MB) of the processes of the sessions ``sids``."""
    total = 0
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            if os.getsid(int(pid)) not in sids:
                continue
            with open("/proc/{}/statm".format(pid)) as f:
                total += int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
        except (OSError, ValueError, IndexError):
            continue
    return total / 2 ** 20


def measured(command, sids):
    """Run ``command`` in a new session; (wall seconds, peak MB of it and ``sids``)."""
    env = dict(os.environ)
    env.pop("GISRC", None)
    start = time.perf_counter()
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True, start_new_session=True, env=env)
    peak = [0.0]

    def sample():
        while proc.poll() is None:
            peak[0] = max(peak[0], sessions_rss(set(sids) | {proc.pid}))
            time.sleep(0.2)

    sampler = threading.Thread(target=sample)
    sampler.start()
    out = proc.communicate()[0]
    sampler.join()
    if proc.returncode:
        print(out)
        raise SystemExit("the run failed")
    return time.perf_counter() - start, peak[0]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def service(*args, check=True, **env):
    """tools/actinia/service.sh with ``args`` and the staged suite (and ``env``)."""
    subprocess.run(["bash", os.path.join(ROOT, "tools", "actinia", "service.sh")] + list(args),
                   check=check, env=dict(os.environ, DIST=DIST, **env),
                   stdout=subprocess.DEVNULL)


def service_sids(folder):
    """The sessions of every process group service.sh started in ``folder``."""
    sids = set()
    for name in os.listdir(folder):
        if name.endswith(".pid"):
            with open(os.path.join(folder, name)) as f:
                sids.add(os.getsid(int(f.read())))
    return sids


def main():
    work = tempfile.mkdtemp(prefix="bench_series_")
    services = [os.path.join(work, "actinia"), os.path.join(work, "actinia_redis")]
    try:
        smap = synthetic_map.generate(seed=1, size=800)
        manifest = synthetic_sheets.write(os.path.join(work, "sheets"), smap, SHEETS, 200.0)
        driver = [sys.executable, os.path.join(ROOT, "tools", "histo_series.py"), manifest]
        rows = []
        seconds, peak = measured(driver + [os.path.join(work, "local"), "--jobs", "1",
                                           "--dist", DIST], set())
        rows.append(("local, sequential", seconds, peak))
        port = free_port()
        sheets = os.path.dirname(manifest)     # the services' work folder (WORK)
        service("start", services[0], str(port), str(free_port()), WORK=sheets)
        sids = service_sids(services[0])
        for jobs in (1, 2):
            seconds, peak = measured(driver + [os.path.join(work, "actinia_{}".format(jobs)),
                                               "--server", "http://127.0.0.1:{}".format(port),
                                               "--credentials", services[0],
                                               "--jobs", str(jobs)], sids)
            rows.append(("actinia, {} worker{}".format(jobs, "s" if jobs > 1 else ""),
                         seconds, peak))
        service("stop", services[0])
        ports = [free_port(), free_port()]
        service("start", services[1], str(ports[0]), str(free_port()), QUEUES="2", WORK=sheets)
        service("server", services[1], str(ports[1]))
        for name in ("a", "b"):
            service("worker", services[1], name)
        servers = [a for p in ports for a in ("--server", "http://127.0.0.1:{}".format(p))]
        seconds, peak = measured(driver + [os.path.join(work, "actinia_redis")] + servers +
                                 ["--credentials", services[1], "--jobs", "2"],
                                 service_sids(services[1]))
        rows.append(("redis queue, 2 servers, 2 workers", seconds, peak))
        print("{} sheets of 200 m x 200 m (synthetic, seed 1)".format(len(SHEETS)))
        print("{:<34} {:>8} {:>13} {:>14}".format("run", "wall s", "sheets/hour", "peak RSS MB"))
        for name, seconds, peak in rows:
            print("{:<34} {:>8.1f} {:>13.0f} {:>14.0f}".format(
                name, seconds, len(SHEETS) * 3600 / seconds, peak))
    finally:
        for folder in services:
            if os.path.isdir(folder):
                service("stop", folder, check=False)
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Strong scaling of a distributed cosim run: the UCS case at --dx (default 2 mm) to a short end
strain (--end-strain, default 0.0005: a few hundred steps; --strain-rate R sets the loading rate,
and with it the step count, instead of the case's derived rate), one thread per rank
(OMP_NUM_THREADS=1, SPH/Threads=1), on 1 rank without mpirun and on 2 (or --ranks) under mpirun,
--rounds times in turn (1, 2, 1, 2, ...: a drift of the machine's speed then touches both rank
counts alike). Each rank runs under /usr/bin/time -v.

Prints and writes OUT/mpi_scaling.csv, a row per run: round, ranks, particles, steps, run wall
seconds (summary.json: the run loop, without setup), particle-steps per second, parallel
efficiency against the 1-rank run of the same round, peak RSS per rank [MiB], CPU seconds per
rank (user + system of the whole process: Open MPI polls while it waits, so waiting counts too),
the peak RSS per owned particle of each rank [KiB], ghost fraction (ghosts held per particle of
the body), the least and most seconds a rank spent in the exchanges and collectives of the run
loop (waiting for the others included), halo bytes per step (all ranks) and the largest
difference of a history.csv column from the 1-rank run's, relative to the column's largest value
(0-based column index; 8 is the dissipated energy). Then, per rank count, the median rate of the
rounds and the efficiency of the medians. On a shared machine the wall-clock rates depend on the
load: the load average is printed with every result.

--serial-rate R takes the 1-rank rate from an earlier run instead of running it (the history is
then not compared).

Usage: tools/mpi_bench.py [--dx DX] [--end-strain E] [--strain-rate R] [--ranks 2,3]
                          [--rounds N] [--serial-rate R] [--out DIR]
"""
import argparse
import csv
import json
import os
import pathlib
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

root = pathlib.Path(__file__).resolve().parent.parent


def peak_rss_mib(path):
    text = pathlib.Path(path).read_text()
    return int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)) / 1024.0


def cpu_seconds(path):
    text = pathlib.Path(path).read_text()
    user = float(re.search(r"User time \(seconds\): ([0-9.]+)", text).group(1))
    system = float(re.search(r"System time \(seconds\): ([0-9.]+)", text).group(1))
    return user + system


def history(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return [[float(x) for x in r] for r in rows[1:]]


def history_difference(a, b):
    """The largest difference of a column of b from a, relative to the column's largest |value|,
    and the column's index (inf for a different row count)."""
    if len(a) != len(b):
        return float("inf"), -1
    worst = (0.0, -1)
    for c in range(len(a[0])):
        scale = max(abs(r[c]) for r in a) or 1.0
        d = max(abs(x[c] - y[c]) for x, y in zip(a, b)) / scale
        worst = max(worst, (d, c))
    return worst


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--dx", type=float, default=0.002)
    p.add_argument("--end-strain", type=float, default=0.0005)
    p.add_argument("--strain-rate", type=float, default=0.0,
                   help="Loading/Strain rate [1/s]; 0 keeps the case's (derived) rate")
    p.add_argument("--ranks", default="2")
    p.add_argument("--rounds", type=int, default=1)
    p.add_argument("--serial-rate", type=float, default=0.0,
                   help="particle-steps/s of an earlier 1-rank run of the same case: the 1-rank "
                        "run is skipped (a 1 mm UCS takes 15 minutes on one core)")
    p.add_argument("--out", default=str(root / "docs" / "results" / "bench"))
    p.add_argument("--cosim", default=os.environ.get("COSIM_BINARY", str(root / "build" / "bin" / "cosim")))
    a = p.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    work = pathlib.Path(tempfile.mkdtemp(prefix="cosim-mpi-bench-"))
    env = dict(os.environ, OMP_NUM_THREADS="1")
    mpirun = ["mpirun", "--oversubscribe"] + (["--allow-run-as-root"] if os.geteuid() == 0 else [])
    results = []
    extra = f" --set 'Loading/Strain rate={a.strain_rate}'" if a.strain_rate > 0 else ""
    try:
        serial = [] if a.serial_rate > 0 else [1]
        for k in range(a.rounds):
            for n in serial + [int(r) for r in a.ranks.split(",")]:
                folder = work / f"round{k}-ranks{n}"
                times = work / f"time{k}-{n}"
                # each rank under /usr/bin/time -v, its report in its own file
                inner = (f"exec /usr/bin/time -v -o {times}.$OMPI_COMM_WORLD_RANK {a.cosim} run "
                         f"{root / 'cases/ucs/ucs.prm'} -o {folder} --quiet "
                         f"--set 'SPH/Particle spacing={a.dx}' --set SPH/Threads=1 "
                         f"--set 'Loading/End strain={a.end_strain}'{extra}")
                if n == 1:
                    command = ["sh", "-c", inner.replace("$OMPI_COMM_WORLD_RANK", "0")]
                else:
                    command = mpirun + ["-np", str(n), "sh", "-c", inner]
                subprocess.run(command, check=True, env=env)
                s = json.loads((folder / "summary.json").read_text())
                rss = [peak_rss_mib(f"{times}.{r}") for r in range(n)]
                cpu = [cpu_seconds(f"{times}.{r}") for r in range(n)]
                rate = s["n_particles"] * s["n_steps"] / s["wall_seconds"]
                owned = s.get("particles_per_rank", [s["n_particles"]])
                results.append(dict(
                    round=k, ranks=n, particles=s["n_particles"], steps=s["n_steps"],
                    wall_s=round(s["wall_seconds"], 2), particle_steps_per_s=round(rate),
                    efficiency=None, peak_rss_mib_per_rank=" ".join(f"{x:.0f}" for x in rss),
                    cpu_s_per_rank=" ".join(f"{x:.1f}" for x in cpu),
                    kib_per_owned_particle=" ".join(f"{1024 * x / c:.2f}" for x, c in zip(rss, owned)),
                    ghost_fraction=round(s.get("ghost_fraction", 0.0), 3),
                    wait_s_min_max="%.1f %.1f" % (s.get("mpi_wait_seconds_min", 0.0),
                                                  s.get("mpi_wait_seconds_max", 0.0)),
                    halo_bytes_per_step=int(s.get("halo_bytes_per_step", 0)),
                    history_difference="%.1e in column %d" % history_difference(
                        history(work / f"round{k}-ranks1" / "history.csv"),
                        history(folder / "history.csv"))
                    if serial else "not compared (--serial-rate)",
                    load=os.getloadavg()[0]))
                base = a.serial_rate if a.serial_rate > 0 else [
                    r for r in results if r["round"] == k and r["ranks"] == 1][0]["particle_steps_per_s"]
                results[-1]["efficiency"] = round(rate / base / n, 3)
                print(results[-1], flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    with open(out / "mpi_scaling.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(results[0].keys()))
        w.writeheader()
        w.writerows(results)
    print(f"written: {out / 'mpi_scaling.csv'}")
    base = a.serial_rate or statistics.median(
        r["particle_steps_per_s"] for r in results if r["ranks"] == 1)
    for n in sorted({r["ranks"] for r in results}):
        rates = [r["particle_steps_per_s"] for r in results if r["ranks"] == n]
        median = statistics.median(rates)
        print(f"{n} rank(s): median {median:,.0f} particle-steps/s over {len(rates)} run(s), "
              f"efficiency of the medians {median / base / n:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

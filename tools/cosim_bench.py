#!/usr/bin/python3
"""Whole coupled runs through `cosim` on 1 and 2 threads: what a user's run costs.

Usage: cosim_bench.py COSIM ROOT OUT_DIR [SPACING=0.0025] [CASES=ucs,bts]

For each case (cases/<name>/<name>.prm) and thread count (SPH/Threads = 1, then 2) it runs
`cosim run` to the case's own end (the full test: setup, SPH, FEM platens, contact, output) and
reports, from that process alone (os.wait4's resource usage) and its summary.json:
  particles, SPH pairs, steps, wall s, CPU s (user + sys), particle-steps per wall second and
  per CPU second, SPH pair interactions per wall second, peak RSS [MB] and per particle,
  and the peak stress (the same run on 1 and 2 threads must give the same result).
Rates include setup and output: they are what a run costs, not the SPH step alone
(`sph_bench` measures that). A small run's RSS is mostly the program itself (deal.II, HDF5,
~150 MB), so each case also runs once on 1 thread at twice the spacing, and the marginal memory
(RSS difference over particle difference) is the cost of a particle in a coupled run (where the
case accepts that spacing: the BTS disc is too thin for 5 mm). Writes
OUT_DIR/cosim_runs.csv and prints the table, the 2-thread speed-up of each case and the
marginal bytes per particle. Exit status 2 on bad arguments or a failed run.
"""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time


def fail(message):
    print("cosim_bench.py: " + message, file=sys.stderr)
    sys.exit(2)


def run_case(cosim, prm, out, spacing, threads, optional=False):
    cmd = [cosim, "run", prm, "-o", out, "--quiet", "--force",
           "--set", "SPH/Particle spacing=%s" % spacing, "--set", "SPH/Threads=%d" % threads]
    # stderr to a file, not a pipe: nobody reads a pipe while os.wait4 waits, and a run that
    # wrote more than the pipe holds would never end
    with tempfile.TemporaryFile("w+") as err_file:
        start = time.monotonic()
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err_file)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.monotonic() - start
        err_file.seek(0)
        err = err_file.read().strip()
    code = os.waitstatus_to_exitcode(status)
    if code == 2 and optional:  # the case refuses that spacing
        print("(%s at %s m: %s)" % (os.path.basename(prm), spacing, err))
        return None
    if code != 0:
        fail("%s failed (exit %d): %s" % (" ".join(cmd), code, err))
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    n, steps = int(s["n_particles"]), int(s["n_steps"])
    pairs = s.get("n_sph_pairs")
    if pairs is None:
        fail("%s/summary.json has no n_sph_pairs (an older cosim?)" % out)
    cpu = usage.ru_utime + usage.ru_stime
    rss = usage.ru_maxrss * 1024.0  # Linux: kilobytes
    return {
        "threads": threads, "particles": n, "pairs": int(pairs), "steps": steps,
        "wall_s": wall, "cpu_s": cpu,
        "particle_steps_per_s": n * steps / wall,
        "particle_steps_per_cpu_s": n * steps / cpu,
        "pair_interactions_per_s": pairs * steps / wall,
        "peak_rss_MB": rss / 2**20, "bytes_per_particle": rss / n,
        "peak_stress_MPa": s["peak_stress_MPa"],
    }


def main():
    if len(sys.argv) < 4 or len(sys.argv) > 6:
        fail("usage: cosim_bench.py COSIM ROOT OUT_DIR [SPACING=0.0025] [CASES=ucs,bts]")
    cosim, root, out_dir = sys.argv[1:4]
    spacing = sys.argv[4] if len(sys.argv) > 4 else "0.0025"
    cases = (sys.argv[5] if len(sys.argv) > 5 else "ucs,bts").split(",")
    try:
        if not float(spacing) > 0:
            raise ValueError
    except ValueError:
        fail("SPACING must be a positive number of metres, got '%s'" % spacing)
    if not os.access(cosim, os.X_OK):
        fail("%s: no such program (build cosim first)" % cosim)
    prms = []
    for c in cases:
        prm = os.path.join(root, "cases", c, c + ".prm")
        if not os.path.isfile(prm):
            fail("%s: no such case file (CASES names folders of cases/)" % prm)
        prms.append((c, prm))
    os.makedirs(out_dir, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="cosim_bench.")
    rows = []
    try:
        coarse = "%g" % (2 * float(spacing))
        for c, prm in prms:
            for threads, dx in ((1, spacing), (2, spacing), (1, coarse)):
                r = run_case(cosim, prm, os.path.join(tmp, "%s_%d_%s" % (c, threads, dx)), dx,
                             threads, optional=dx == coarse)
                if r is None:
                    continue
                r["case"], r["spacing_m"] = c, float(dx)
                rows.append(r)
                print("%-4s %s m %d thread(s): %6d particles %8d pairs %5d steps  wall %6.1f s  "
                      "CPU %6.1f s  %.3g particle-steps/s (%.3g per CPU s)  %.3g pair "
                      "interactions/s  peak RSS %.0f MB (%.0f B/particle)  peak %.4f MPa"
                      % (c, dx, threads, r["particles"], r["pairs"], r["steps"], r["wall_s"],
                         r["cpu_s"], r["particle_steps_per_s"], r["particle_steps_per_cpu_s"],
                         r["pair_interactions_per_s"], r["peak_rss_MB"],
                         r["bytes_per_particle"], r["peak_stress_MPa"]), flush=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    keys = ["case", "spacing_m", "threads", "particles", "pairs", "steps", "wall_s", "cpu_s",
            "particle_steps_per_s", "particle_steps_per_cpu_s", "pair_interactions_per_s",
            "peak_rss_MB", "bytes_per_particle", "peak_stress_MPa"]
    path = os.path.join(out_dir, "cosim_runs.csv")
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(keys)
        for r in rows:
            w.writerow([r[k] if isinstance(r[k], (int, str)) else "%.6g" % r[k] for k in keys])
    for c, _ in prms:
        one, two, *small = [r for r in rows if r["case"] == c]
        print("%-4s speed-up 2 threads / 1 thread: %.2f (wall); peak stress %s on 1 and 2 threads"
              % (c, one["wall_s"] / two["wall_s"],
                 "the same" if one["peak_stress_MPa"] == two["peak_stress_MPa"] else
                 "DIFFERS (%.10g against %.10g)" % (one["peak_stress_MPa"],
                                                    two["peak_stress_MPa"])))
        if not small:
            continue
        small = small[0]
        dn = one["particles"] - small["particles"]
        if dn > 0:
            print("%-4s marginal memory: %.0f B per particle (%.0f MB at %d particles, %.0f MB at "
                  "%d)" % (c, (one["peak_rss_MB"] - small["peak_rss_MB"]) * 2**20 / dn,
                           one["peak_rss_MB"], one["particles"], small["peak_rss_MB"],
                           small["particles"]))
    print("wrote", path)


if __name__ == "__main__":
    main()

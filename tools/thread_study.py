#!/usr/bin/python3
"""Where the second thread goes: interleaved rounds of sph_bench (2-thread target 1.8x).

Usage: thread_study.py SPH_BENCH OUT_DIR [ROUNDS=8] [STEPS=40] [SPACING=0.00125]

Each round runs, one after the other:
  one      1 thread: the per-core rate;
  two      2 threads, OpenMP's default wait policy (what cosim runs with: a waiting
           thread spins a while, then sleeps): the speed-up, wall of `one` / wall of `two`,
           paired per round;
  passive  the same with OMP_WAIT_POLICY=passive: a thread that waits at a barrier sleeps
           instead of spinning, so its CPU time is its work;
  single   1 thread, the particles in one chunk (Parameters::chunks = 1) instead of the
           automatic chunks every run uses: what the decomposition itself costs (the pairs
           across chunks), free of any contention between cores; its results differ from the
           others' by round-off (the order of the sums), so its checksum is not compared;
  pair     two 1-thread runs at once, as separate processes: what the machine's two cores cost
           each other (shared memory path, co-tenants) with no shared data and no barriers.
Runs other than `two` use OMP_WAIT_POLICY=passive (CPU time = work). The CPU ratios
passive/one, one/single and pair/one split the second thread's loss into the code's part
(the chunks), the machine's part (pair) and the rest (threads of one process). Writes
OUT_DIR/threads.csv (every run) and threads_summary.txt.

Rates are particle-steps per CPU second (one) and per wall second (two). Medians and the best
run are both given: on a shared VM the noise only ever slows a run down, so the best of the
interleaved runs measures the code and the median measures the machine as it was.
"""
import os
import statistics
import subprocess
import sys


def run(bench, spacing, steps, threads, extra_env=None, background=False, chunks=0):
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMP_", "GOMP_"))}
    env["OMP_WAIT_POLICY"] = "passive"
    env.update(extra_env or {})
    env = {k: v for k, v in env.items() if v is not None}
    cmd = [bench, spacing, str(steps), str(threads), "mixed", str(chunks)]
    if background:
        return subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True, env=env)
    return parse(subprocess.run(cmd, stdout=subprocess.PIPE, text=True, env=env, check=True).stdout)


def parse(out):
    r = {}
    for line in out.splitlines():
        f = line.split()
        if line.startswith("particles "):
            r["particles"], r["wall"] = int(f[1]), float(f[10])
        elif line.startswith("cpu "):
            r["cpu"] = float(f[1])
        elif line.startswith("state checksum"):
            r["checksum"] = f[2]
    if len(r) != 4:
        sys.exit("thread_study.py: unexpected sph_bench output:\n" + out)
    return r


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    bench, out = sys.argv[1], sys.argv[2]
    try:
        rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 8
        steps = int(sys.argv[4]) if len(sys.argv) > 4 else 40
        spacing = sys.argv[5] if len(sys.argv) > 5 else "0.00125"
        ok = rounds >= 2 and steps >= 1 and float(spacing) > 0
    except ValueError:
        ok = False
    if not ok:
        print("thread_study.py: ROUNDS must be an integer >= 2, STEPS an integer >= 1 and "
              "SPACING a number > 0 (got %s)" % " ".join(sys.argv[3:]), file=sys.stderr)
        sys.exit(2)
    rows = []  # (round, variant, wall, cpu)
    checksums = set()
    for k in range(rounds):
        one = run(bench, spacing, steps, 1)
        two = run(bench, spacing, steps, 2, {"OMP_WAIT_POLICY": None})
        passive = run(bench, spacing, steps, 2)
        single = run(bench, spacing, steps, 1, chunks=1)
        procs = [run(bench, spacing, steps, 1, background=True) for _ in range(2)]
        pair = [parse(p.communicate()[0]) for p in procs]
        for name, r in (("one", one), ("two", two), ("passive", passive), ("single", single),
                        ("pair_a", pair[0]), ("pair_b", pair[1])):
            rows.append((k, name, r["wall"], r["cpu"]))
            if name != "single":
                checksums.add(r["checksum"])
        print("round %d: one %.2f s | two %.2f s wall | passive %.2f s wall, %.2f CPU s | "
              "single %.2f CPU s | pair %.2f %.2f CPU s"
              % (k, one["wall"], two["wall"], passive["wall"], passive["cpu"], single["cpu"],
                 pair[0]["cpu"], pair[1]["cpu"]), flush=True)
    n = one["particles"] * steps

    def col(name, key):
        return [r[2 if key == "wall" else 3] for r in rows if r[1] == name]

    def paired(f):
        return statistics.median(f(k) for k in range(rounds))

    by = {(r[0], r[1]): r for r in rows}
    one_cpu, one_wall, two_wall = col("one", "cpu"), col("one", "wall"), col("two", "wall")
    lines = [
        "sph_bench %s %d T: %d particles, %d interleaved rounds"
        % (spacing, steps, one["particles"], rounds),
        "results bitwise equal in every variant but single: %s"
        % ("yes" if len(checksums) == 1 else "NO"),
        "1 thread, particle-steps per CPU s: median %.3g, best %.3g (quartiles %.3g .. %.3g)"
        % (n / statistics.median(one_cpu), n / min(one_cpu),
           n / statistics.quantiles(one_cpu, n=4)[2], n / statistics.quantiles(one_cpu, n=4)[0]),
        "2 threads (default wait policy), particle-steps per wall s: median %.3g, best %.3g"
        % (n / statistics.median(two_wall), n / min(two_wall)),
        "speed-up 2 threads / 1 thread: median of paired rounds %.2f, of the best runs %.2f"
        % (paired(lambda k: by[(k, "one")][2] / by[(k, "two")][2]), min(one_wall) / min(two_wall)),
        "  with OMP_WAIT_POLICY=passive: median of paired rounds %.2f"
        % paired(lambda k: by[(k, "one")][2] / by[(k, "passive")][2]),
        "CPU time / 1 thread (medians of paired rounds):",
        "  chunks against one chunk (the decomposition)   %.3f"
        % paired(lambda k: by[(k, "one")][3] / by[(k, "single")][3]),
        "  two 1-thread processes at once (the machine)   %.3f"
        % paired(lambda k: 0.5 * (by[(k, "pair_a")][3] + by[(k, "pair_b")][3]) / by[(k, "one")][3]),
        "  2 threads of one process (passive wait)        %.3f"
        % paired(lambda k: by[(k, "passive")][3] / by[(k, "one")][3]),
    ]
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "threads.csv"), "w") as f:
        f.write("round,variant,wall_s,cpu_s\n")
        for r in rows:
            f.write("%d,%s,%.3f,%.3f\n" % r)
    with open(os.path.join(out, "threads_summary.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    print("wrote", os.path.join(out, "threads.csv"), "and threads_summary.txt")


if __name__ == "__main__":
    main()

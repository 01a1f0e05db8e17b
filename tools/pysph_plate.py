#!/usr/bin/python3
"""PySPH's solid_mech/oscillating_plate example, timed: run with Debian's /usr/bin/python3
(python3-pysph). One change to the example: the edge velocity Vf (default 0.01 instead of the
example's 0.05, whose tip amplitude exceeds the plate length and leaves the small-deflection
theory both codes are checked against). Serial (no --openmp), no output files.

Usage: pysph_plate.py STEPS [VF] [DX]
DX (default the example's 0.002 m) refines the plate; h stays 1.3 DX as in the example.
Prints particles, steps, wall and CPU seconds of the time loop only (set-up and Cython
compilation excluded), particle-steps/s, and the period from the tip's first downward zero
crossing (t = T/2 for y = A sin(omega t)) against thin-plate theory. PySPH's EPEC integrator
evaluates the forces twice per step; a step is counted as one step, as ours is.
"""
import math
import sys
import tempfile
import time

from pysph.examples.solid_mech.oscillating_plate import OscillatingPlate


class TimedPlate(OscillatingPlate):
    def initialize(self):
        super().initialize()
        self.Vf = self.vf_override
        self.dx_plate = self.dx_override
        self.h = 1.3 * self.dx_plate
        self.trace = []
        self.cpu0 = self.wall0 = None

    def post_step(self, solver):
        if self.cpu0 is None:  # after the first step: excludes set-up and compilation
            self.cpu0, self.wall0 = time.process_time(), time.perf_counter()
            self.steps0 = solver.count
        plate = self.particles[0]
        self.trace.append((solver.t, plate.y[plate.amplitude_idx[0]]))


def main():
    steps = int(sys.argv[1]) if len(sys.argv) > 1 else 15000
    TimedPlate.vf_override = float(sys.argv[2]) if len(sys.argv) > 2 else 0.01
    TimedPlate.dx_override = float(sys.argv[3]) if len(sys.argv) > 3 else 0.002
    app = TimedPlate()
    dt = 1e-5
    out = tempfile.mkdtemp(prefix="pysph_plate_")
    app.run(["--tf", repr(steps * dt), "--disable-output", "-d", out, "-q"])
    cpu = time.process_time() - app.cpu0
    wall = time.perf_counter() - app.wall0
    n_timed = app.solver.count - app.steps0
    n = sum(pa.get_number_of_particles() for pa in app.particles)
    t_half = -1.0
    prev = None
    for t, y in app.trace:
        d = y - 0.0  # the tip particle starts at y = 0
        if prev is not None and prev[1] > 0 and d <= 0:
            t_half = t - (t - prev[0]) * d / (d - prev[1])
            break
        prev = (t, d)
    E, nu, rho, H, L = 2e6, 0.3975, 1000.0, 0.02, 0.2
    k = 1.875 / L
    omega = math.sqrt(E * H * H * k**4 / (12 * rho * (1 - nu * nu)))
    print("particles %d" % n)
    print("steps %d" % app.solver.count)
    print("dt %g" % app.solver.dt)
    print("dx %g" % app.dx_plate)
    print("wall_s %.3f" % wall)
    print("cpu_s %.3f" % cpu)
    print("particle_steps_per_s %.4g" % (n * n_timed / wall))
    print("particle_steps_per_cpu_s %.4g" % (n * n_timed / cpu))
    print("analytic_period_s %.5f" % (2 * math.pi / omega))
    print("measured_period_s %.5f" % (2 * t_half if t_half > 0 else -1.0))


if __name__ == "__main__":
    main()

#include "test_helpers.h"

#include <cmath>

namespace sph_test
{
  MaterialParameters basalt_elastic()
  {
    MaterialParameters m;
    m.model          = RockModel::elastic;
    m.density        = 2900;
    m.youngs_modulus = 97.07e9;
    m.poissons_ratio = 0.28;
    return m;
  }

  double p_wave_speed(const MaterialParameters &m)
  {
    return std::sqrt(m.youngs_modulus * (1 - m.poissons_ratio) /
                     ((1 + m.poissons_ratio) * (1 - 2 * m.poissons_ratio) * m.density));
  }

  AxialResult axial_test(const Parameters &prm, const MaterialParameters &mat, const double D,
                         const double L, const double strain, const double ramp_transits,
                         const double hold_transits, const double damping)
  {
    const Lattice<3> lat = make_cylinder<3>(D, L, prm.spacing);
    Body<3>          body(prm, mat, lat.positions, lat.volumes);
    const unsigned   n = body.n_particles();
    double           zmin = 1e30, zmax = -1e30;
    for (const auto &x : lat.positions)
      {
        zmin = std::min(zmin, x[2]);
        zmax = std::max(zmax, x[2]);
      }
    const double dz = L / std::lround(L / prm.spacing), gauge = zmax - zmin;
    // extensometer planes near L/4 and 3L/4, radial gauge at mid-height
    const double zl = zmin + std::round((0.25 * L - zmin) / dz) * dz;
    const double zu = zmin + std::round((0.75 * L - zmin) / dz) * dz;
    const double zm = zmin + std::round((0.5 * L - zmin) / dz) * dz;
    std::vector<int> role(n, 0); // 1 bottom, 2 top, 3 lower gauge, 4 upper gauge, 5 radial gauge
    for (unsigned i = 0; i < n; ++i)
      {
        const Vector<3> &x = lat.positions[i];
        const double     r = std::hypot(x[0], x[1]);
        if (std::abs(x[2] - zmin) < 0.25 * dz)
          role[i] = 1;
        else if (std::abs(x[2] - zmax) < 0.25 * dz)
          role[i] = 2;
        else if (std::abs(x[2] - zl) < 0.25 * dz)
          role[i] = 3;
        else if (std::abs(x[2] - zu) < 0.25 * dz)
          role[i] = 4;
        else if (std::abs(x[2] - zm) < 0.25 * dz && r > 0.3 * D)
          role[i] = 5;
      }
    const double c = body.wave_speed(), transit = L / c;
    const double t_ramp = ramp_transits * transit, t_end = t_ramp + hold_transits * transit;
    const double delta  = strain * gauge;          // end displacement of the top layer
    const double v_mean = delta / t_ramp;          // v(t) = v_mean (1 - cos(2 pi t / t_ramp))
    const double area   = lat.true_section_area;
    AxialResult  out;
    double       t = 0;
    while (t < t_end)
      {
        body.compute_forces();
        const double dt = body.stable_time_step();
        const double tm = t + 0.5 * dt;
        const double v_top =
          tm < t_ramp ? v_mean * (1.0 - std::cos(2.0 * M_PI * tm / t_ramp)) : 0.0;
        auto &f_ext = body.external_forces();
        for (unsigned i = 0; i < n; ++i)
          {
            if (role[i] == 1)
              body.constrain(i, 2, 0.0);
            else if (role[i] == 2)
              body.constrain(i, 2, v_top);
            else if (damping > 0)
              {
                // axial dynamic relaxation about the affine velocity field (no radial damping:
                // it would confine the specimen)
                const double v_aff = v_top * (body.reference_positions()[i][2] - zmin) / gauge;
                f_ext[i][2] -= damping * body.masses()[i] * (body.velocities()[i][2] - v_aff);
              }
          }
        body.integrate(dt);
        t += dt;
        ++out.steps;
        double f_top = 0, f_bottom = 0;
        for (unsigned i = 0; i < n; ++i)
          if (role[i] == 1)
            f_bottom += body.reaction_force(i)[2];
          else if (role[i] == 2)
            f_top += body.reaction_force(i)[2];
        // compression: the bottom wall pushes up (+), the top wall down (-)
        const double s = 0.5 * (f_top - f_bottom) / area;
        out.stress     = std::abs(s);
        out.peak_stress = std::max(out.peak_stress, out.stress);
      }
    double ul = 0, uu = 0, ur = 0;
    int    nl = 0, nu = 0, nr = 0;
    for (unsigned i = 0; i < n; ++i)
      {
        const Vector<3> &x0 = body.reference_positions()[i], &x = body.positions()[i];
        if (role[i] == 3)
          ul += x[2] - x0[2], ++nl;
        else if (role[i] == 4)
          uu += x[2] - x0[2], ++nu;
        else if (role[i] == 5)
          {
            const double r0 = std::hypot(x0[0], x0[1]);
            ur += ((x[0] - x0[0]) * x0[0] + (x[1] - x0[1]) * x0[1]) / (r0 * r0);
            ++nr;
          }
      }
    out.strain = std::abs((uu / nu - ul / nl) / (zu - zl));
    out.radial = ur / nr;
    const Energies e  = body.energies();
    out.kinetic_ratio = e.kinetic / std::max(e.internal, 1e-300);
    return out;
  }
} // namespace sph_test

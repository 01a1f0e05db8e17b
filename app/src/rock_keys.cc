// Case-file keys of the Rock section: the material (sph::MaterialParameters; angles written in
// degrees, stored in radians) and what only the case has (group, strength source, scatter). Keys
// left empty take the group's value (resolve_rock).
#include "case_keys.h"

#include <diagnose/calibrate.h>
#include <diagnose/material_table.h>
#include <sph/rock_models.h>

#include <cmath>

namespace app::keys
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    double radians(double degrees) { return degrees * pi / 180.0; }
    double degrees(double radians) { return radians * 180.0 / pi; }
  } // namespace

  void declare_rock_keys(Section &s, coupling::CaseParameters &p, RockOverrides &o)
  {
    sph::MaterialParameters &m = p.rock;
    coupling::RockCase &c      = p.rock_case;
    const auto mohr_coulomb    = [&m]() {
      return m.model == sph::RockModel::mohr_coulomb || m.model == sph::RockModel::mohr_coulomb_cutoff;
    };
    s.add("Group", c.group, "material group looked up in the data folder (M1..M10)");
    s.add_enum("Model", m.model, "elastic|mohr-coulomb|mohr-coulomb-cutoff|hoek-brown",
               {sph::RockModel::elastic, sph::RockModel::mohr_coulomb, sph::RockModel::mohr_coulomb_cutoff,
                sph::RockModel::hoek_brown},
               "constitutive model of the rock");
    s.add_choice("Strength parameters", c.strength_source, "calibrated|simulated|measured|brazilian|envelope",
                 "c, phi from Table 4 (calibrated to UCS and BTS by the closed forms), simulated (those with which the simulator reproduces the group's UCS and BTS: simulator_calibrated.csv, cosim calibrate --simulate --with-bts on the flattened body-fitted disc; with Rock/Model = hoek-brown the envelope below with the cut-off of that table, cosim calibrate --simulate --cutoff-from, or for a group without triaxial data a = 1/2 and that table's m_b, no cut-off but the envelope's apex, cosim calibrate --simulate --mb-from), Table 3 (measured by CTCS, groups M8-M10) or brazilian (calibrated to UCS and to BTS at the disc centre's stress state, cosim calibrate --brazilian); envelope: with Rock/Model = hoek-brown, sigma_ci, m_b and a fitted to all of the group's strengths (UCS, BTS at the disc centre's state, Table 3's measured envelope at 10, 30, 50 MPa where it has one) and a tension cut-off at the BTS (cosim calibrate --envelope)");
    s.add("Data directory", c.data_directory,
          "folder with table3_fitted_parameters.csv, table4_calibrated.csv, simulator_calibrated.csv; empty = cases/data");
    s.add<double>("Density", m.density, "[kg/m^3] (not in the paper: a typical basalt value)",
                  [](double v) { return v > 0 && v < 30000; }, "must be in (0, 30000) kg/m^3");
    s.add_optional("Youngs modulus", o.youngs_modulus, "[Pa]; empty = from Rock/Group");
    s.check("Youngs modulus", [&m]() {
      return m.youngs_modulus > 0 && m.youngs_modulus < 1e13 ? "" : "must be in (0, 1e13) Pa (basalt: about 1e11)";
    });
    s.add_optional("Poissons ratio", o.poissons_ratio, "[-]; empty = from Rock/Group");
    s.check("Poissons ratio",
            [&m]() { return m.poissons_ratio >= 0 && m.poissons_ratio < 0.5 ? "" : "must be in [0, 0.5)"; });
    s.add_optional("Cohesion", o.cohesion, "[Pa]; empty = from Rock/Group");
    s.check("Cohesion", [&m]() { return m.cohesion > 0 ? "" : "must be > 0 Pa"; });
    s.add_optional("Friction angle", o.friction_angle_deg, "[deg]; empty = from Rock/Group");
    s.check("Friction angle", [&m]() {
      const double phi = degrees(m.friction_angle);
      return phi > 0 && phi < 90 ? "" : "must be in (0, 90) degrees";
    });
    s.add_degrees("Dilation angle", m.dilation_angle, "[deg], at most the friction angle",
                  [](double v) { return v >= 0; }, "must be >= 0 degrees");
    s.check("Dilation angle", [&m]() {
      return m.dilation_angle <= m.friction_angle
               ? std::string()
               : "must be in [0, friction angle = " + format(degrees(m.friction_angle)) + "] degrees";
    });
    s.add_optional("Tensile strength", o.tensile_strength,
                   "tension cut-off [Pa]; empty = the group's BTS for mohr-coulomb-cutoff, else none");
    s.check("Tensile strength", [&m]() {
      if (m.tensile_strength < 0)
        return std::string("must be >= 0 Pa");
      if (m.model != sph::RockModel::mohr_coulomb_cutoff)
        return std::string();
      const double apex = m.cohesion / std::tan(m.friction_angle);
      return m.tensile_strength > 0 && m.tensile_strength <= apex
               ? std::string()
               : "must be in (0, c/tan(phi) = " + format(apex) + "] Pa for mohr-coulomb-cutoff";
    });
    s.add_optional("Hoek-Brown mi", o.hb_mi,
                   "Hoek-Brown m_i [-]; empty = 25 (basalt), or the fit of Rock/Strength parameters = envelope");
    s.check("Hoek-Brown mi", [&m]() {
      return m.model != sph::RockModel::hoek_brown || (m.hb_mb > 0 && m.hb_mb < 200) ? "" : "must be in (0, 200) for hoek-brown";
    });
    s.add_optional("Hoek-Brown a", o.hb_a,
                   "Hoek-Brown exponent a [-]; empty = 0.5 (intact rock), or the fit of Rock/Strength parameters = envelope");
    s.check("Hoek-Brown a", [&m]() {
      return m.model != sph::RockModel::hoek_brown || (m.hb_a >= 0.3 && m.hb_a < 1) ? "" : "must be in [0.3, 1) for hoek-brown";
    });
    s.add_optional("UCS", o.ucs, "uniaxial strength sigma_ci [Pa]; empty = from Rock/Group");
    s.check("UCS", [&m]() {
      return m.model != sph::RockModel::hoek_brown || m.hb_sigma_ci > 0 ? "" : "must be > 0 Pa for hoek-brown";
    });
    s.add<double>("Softening strain", m.softening_strain, "plastic strain to residual strength [-]",
                  [](double v) { return v > 0 && v < 1; }, "must be in (0, 1)");
    s.add_enum("Softening law", m.softening_law, "strain|fracture energy",
               {sph::SofteningLaw::strain, sph::SofteningLaw::fracture_energy},
               "how the strength softens after its peak: strain (linearly in the equivalent "
               "plastic strain to "
               "the residual at Rock/Softening strain) or fracture energy (crack band: each "
               "particle dissipates "
               "Rock/Fracture energy per unit crack area over a band two particle spacings wide "
               "(at CSLH 1.2), so that results do "
               "not move with SPH/Particle spacing); Rock/Softening strain is the strain law's, "
               "Rock/Fracture "
               "energy and Rock/Shear fracture energy ratio the crack band's");
    s.add<double>(
      "Fracture energy", m.fracture_energy,
      "mode I fracture energy G_I [J/m^2] (Rock/Softening law = fracture energy); 100: basalt, "
      "K_Ic = 2.7-3.8 MPa m^0.5 (Balme et al. 2004) gives K_Ic^2 (1 - nu^2)/E = 69-137 J/m^2",
      [](double v) { return v > 0 && v < 1e6; }, "must be in (0, 1e6) J/m^2");
    s.check("Fracture energy", [&p]() {
      const sph::MaterialParameters &r = p.rock;
      if (r.softening_law != sph::SofteningLaw::fracture_energy ||
          r.model == sph::RockModel::elastic)
        return std::string();
      const double h_max = sph::rock::max_crack_band_width(r);
      const double band  = sph::rock::crack_band_width(p.sph.spacing, p.sph.cslh);
      if (band < h_max)
        return std::string();
      const double ft = sph::rock::uniaxial_tensile_strength(r);
      return "the softening would snap back: the crack band (" + format(band) +
             " m at SPH/Particle spacing = " + format(p.sph.spacing) +
             " m) must be narrower than 2 E G_I / f_t^2 = " + format(h_max) +
             " m (f_t = " + format(ft) + " Pa); needs G_I > f_t^2 h / (2 E) = " +
             format(ft * ft * band / (2 * r.youngs_modulus)) + " J/m^2, or a finer spacing";
    });
    s.add<double>(
      "Shear fracture energy ratio", m.shear_fracture_energy_ratio,
      "G_II / G_I [-]: the fracture energy of shear and crushing returns over Rock/Fracture "
      "energy; 6.25 = 2.5^2, rock's K_IIc being 2-3 K_Ic (Rao 1999; Backers et al. 2002); a "
      "shear fault's energy, about 1e4 J/m^2 (Wong 1982), is 100: with it the crack band "
      "regularises compressive failure too at spacings below 12 mm (docs/design.md)",
      [](double v) { return v >= 1 && v <= 1000; }, "must be in [1, 1000]");
    s.add<double>("Residual fraction", m.residual_fraction, "residual / peak strength [-]",
                  [](double v) { return v >= 0 && v <= 1; }, "must be in [0, 1]");
    s.add_optional("Residual friction angle", o.residual_friction_angle_deg,
                   "[deg] friction angle of fully damaged (crushed) rock, reached with the residual strength; empty = the friction angle throughout (mohr-coulomb models)");
    s.check("Residual friction angle", [&m, &o, mohr_coulomb]() {
      if (!o.residual_friction_angle_deg)
        return std::string();
      if (!mohr_coulomb())
        return std::string("softens the Mohr-Coulomb friction angle; Rock/Model = ") +
               (m.model == sph::RockModel::elastic ? "elastic" : "hoek-brown") + " has none (leave it empty)";
      const double phi_r = *o.residual_friction_angle_deg, phi = degrees(m.friction_angle);
      if (!(phi_r > 0 && m.residual_friction_angle <= m.friction_angle))
        return "must be in (0, friction angle = " + format(phi) + "] degrees";
      if (!(m.residual_friction_angle >= m.dilation_angle))
        return "must be at least Rock/Dilation angle = " + format(degrees(m.dilation_angle)) + " degrees";
      return std::string();
    });
    s.add<double>("Strength scatter", c.strength_scatter,
                  "Weibull modulus m of a per-particle strength factor (mean 1) on c, tensile strength and Hoek-Brown s; 0 = homogeneous rock, else >= 1 (rock: about 5-20)",
                  [](double v) { return v == 0 || (v >= 1 && v <= 1000); },
                  "must be 0 (homogeneous) or a Weibull modulus in [1, 1000]");
    s.check("Strength scatter", [&m, &c]() {
      return c.strength_scatter == 0 || m.model != sph::RockModel::elastic
               ? ""
               : "scatters strength, which Rock/Model = elastic does not have; set it to 0 or choose a plastic model";
    });
    s.add<int>("Scatter seed", c.scatter_seed, "seed of the strength scatter: the same seed, the same rock",
               [](int v) { return v >= 0; }, "must be >= 0");
    s.add<double>("Scatter length", c.scatter_length,
                  "[m] correlation length of the strength scatter: the edge of the cubic cells (fixed in space) whose particles share one strength factor, so that a finer SPH/Particle spacing resolves the same rock; 0 = one factor per particle (the rock then changes with the spacing)",
                  [](double v) { return v >= 0 && v < 10; }, "must be in [0, 10) m (0 = one factor per particle)");
    s.check("Scatter length", [&c]() {
      return c.scatter_length == 0 || c.strength_scatter > 0
               ? ""
               : "is used with Rock/Strength scatter > 0 only; leave it at 0";
    });
    // crack closure (toe) elasticity, sph/crack_closure.h: the law `cosim diagnose` fits
    s.add<double>("Closure modulus ratio", m.closure_modulus_ratio,
                  "crack closure: Young's modulus at zero compressive stress E0 / E [-]; 1 = no crack closure (linear elastic)",
                  [](double v) { return v > 0 && v <= 1; }, "must be in (0, 1] (1 = no crack closure)");
    s.add<double>("Closure stress", m.closure_stress,
                  "crack closure: compressive stress sigma_cc over which the modulus rises from E0 to E [Pa] (1/E_t = 1/E + (1/E0 - 1/E) exp(-p/sigma_cc))",
                  [](double v) { return v > 0 && v < 1e10; }, "must be in (0, 1e10) Pa");
    s.check("Closure stress", [&m]() {
      return m.closure_modulus_ratio < 1 || m.closure_stress == sph::MaterialParameters().closure_stress
               ? ""
               : "is used with Rock/Closure modulus ratio < 1 only; leave it at its default (2e7 Pa)";
    });
    // rate-dependent strength, sph/rate_strength.h: the law `cosim diagnose` fits
    s.add<double>("Rate sensitivity", c.rate_sensitivity,
                  "strength gain per decade of the nominal strain rate A [-]: strengths x max(1 + A log10(rate / reference rate), 0.1); 0 = rate independent",
                  [](double v) { return v >= 0 && v <= 1; }, "must be in [0, 1] (rock: about 0.02-0.1; 0 = rate independent)");
    s.check("Rate sensitivity", [&m, &c, &p]() {
      if (c.rate_sensitivity == 0)
        return std::string();
      if (m.model == sph::RockModel::elastic)
        return std::string("scales strength, which Rock/Model = elastic does not have; set it to 0 or choose a plastic model");
      if (p.test != "UCS" && p.test != "BTS" && p.test != "CTCS")
        return "needs the nominal strain rate of a UCS, BTS or CTCS test; Test/Type = " + p.test + " has none (set it to 0)";
      return std::string();
    });
    s.add<double>("Reference strain rate", c.reference_strain_rate,
                  "rate-dependent strength: the strain rate at which the strengths are as given [1/s] (quasi-static; diagnose uses 1e-5)",
                  [](double v) { return v > 0 && v <= 100; }, "must be in (0, 100] 1/s");
    s.check("Reference strain rate", [&c]() {
      return c.rate_sensitivity > 0 || c.reference_strain_rate == coupling::RockCase().reference_strain_rate
               ? ""
               : "is used with Rock/Rate sensitivity > 0 only; leave it at its default (1e-5 1/s)";
    });
  }

  void resolve_rock(coupling::CaseParameters &p, RockOverrides &o, const diagnose::MaterialTable &table,
                    const diagnose::MaterialGroup &group,
                    const std::function<void(const std::string &, const std::string &)> &fail)
  {
    sph::MaterialParameters &m = p.rock;
    coupling::RockCase &c      = p.rock_case;
    std::optional<double> group_c, group_phi; // [Pa], [deg]
    if (c.strength_source == "brazilian")
    {
      // the disc centre's stress state (3 BTS, -BTS) on the envelope instead of uniaxial tension
      if (!(group.ucs > 4 * group.bts))
        fail("Rock/Strength parameters", "brazilian needs UCS > 4 BTS (group " + c.group + ")");
      const diagnose::MohrCoulombStrength b = diagnose::calibrate_mohr_coulomb_brazilian(group.ucs, group.bts);
      group_c   = b.cohesion;
      group_phi = b.friction_angle;
    }
    else if (c.strength_source == "envelope" ||
             (c.strength_source == "simulated" && m.model == sph::RockModel::hoek_brown))
    {
      if (m.model != sph::RockModel::hoek_brown)
        fail("Rock/Strength parameters", "envelope fits a Hoek-Brown envelope: set Rock/Model = hoek-brown");
      if (o.hb_mi || o.hb_a)
        fail(o.hb_mi ? "Rock/Hoek-Brown mi" : "Rock/Hoek-Brown a",
             "is fitted by Rock/Strength parameters = " + c.strength_source +
               ": leave it empty, or choose calibrated");
      const double ucs = o.ucs.value_or(group.ucs);
      if (!(ucs > 4 * group.bts && group.bts > 0))
        fail("Rock/Strength parameters", "envelope needs UCS > 4 BTS > 0 (group " + c.group + ": UCS " +
                                           format(ucs) + " Pa, BTS " + format(group.bts) + " Pa)");
      const auto triaxial = diagnose::triaxial_strengths(group);
      for (const auto &x : triaxial)
        if (!(x.sigma1 > x.sigma3))
          fail("Rock/Strength parameters", "envelope: group " + c.group + "'s measured c, phi give no triaxial strength");
      const diagnose::HoekBrownStrength h = diagnose::calibrate_hoek_brown(ucs, group.bts, triaxial);
      o.hb_mi = h.m_b;
      o.hb_a  = h.a;
      if (c.strength_source == "simulated" && triaxial.empty())
      {
        // no triaxial data: a = 1/2 and the m_b with which the envelope, with no cut-off but its
        // own tensile apex, gives the group's BTS in the simulator's disc
        if (!group.simulated_mb)
          fail("Rock/Strength parameters",
               "simulated with Rock/Model = hoek-brown: group " + c.group +
                 " has no triaxial data and no mb in simulator_calibrated.csv of the data folder "
                 "(cosim calibrate --simulate ... --mb-from finds one); or use envelope");
        o.hb_mi = *group.simulated_mb;
        if (!o.tensile_strength)
          o.tensile_strength = 0.0; // none: the apex s sigma_ci / m_b cuts off
      }
      else if (!o.tensile_strength && c.strength_source == "simulated")
      {
        // the cut-off with which this envelope gives the group's BTS in the simulator's disc
        if (!group.simulated_cutoff)
          fail("Rock/Strength parameters",
               "simulated with Rock/Model = hoek-brown: group " + c.group +
                 " has no cutoff_MPa in simulator_calibrated.csv of the data folder (cosim calibrate "
                 "--simulate ... --cutoff-from finds one where the envelope was fitted to triaxial "
                 "data); or use envelope (the cut-off at the BTS)");
        o.tensile_strength = *group.simulated_cutoff;
      }
      if (!o.tensile_strength)
        o.tensile_strength = h.tensile;
    }
    else if (c.strength_source == "simulated")
    {
      if (!group.simulated_cohesion)
        fail("Rock/Strength parameters",
             "simulated: group " + c.group + " has no row in simulator_calibrated.csv of the data folder; "
             "cosim calibrate --simulate ... --with-bts finds its c, phi, or use calibrated");
      group_c   = group.simulated_cohesion;
      group_phi = group.simulated_friction_angle;
    }
    else if (c.strength_source == "measured")
    {
      if (!group.measured_cohesion)
        fail("Rock/Strength parameters", "group " + c.group + " has no measured c, phi (Table 3); groups that have them: " +
                                           table.groups_with_measured_strength() + "; or use calibrated");
      group_c   = group.measured_cohesion;
      group_phi = group.measured_friction_angle;
    }
    else
    {
      group_c   = group.calibrated_cohesion;
      group_phi = group.calibrated_friction_angle;
    }
    m.youngs_modulus = o.youngs_modulus.value_or(group.youngs_modulus);
    m.poissons_ratio = o.poissons_ratio.value_or(group.poissons_ratio);
    c.ucs            = o.ucs.value_or(group.ucs);
    m.hb_sigma_ci    = c.ucs;
    c.bts            = group.bts;
    m.hb_mb          = o.hb_mi.value_or(25.0);
    m.hb_a           = o.hb_a.value_or(0.5);
    const bool cutoff  = m.model == sph::RockModel::mohr_coulomb_cutoff;
    m.tensile_strength = o.tensile_strength.value_or(cutoff ? group.bts : 0.0);
    const bool needs_mc = m.model == sph::RockModel::mohr_coulomb || cutoff;
    if (o.cohesion)
      m.cohesion = *o.cohesion;
    else if (group_c)
      m.cohesion = *group_c;
    else if (needs_mc)
      fail("Rock/Group", "has no calibrated c, phi (no table4_calibrated.csv row); set Rock/Cohesion and Rock/Friction angle");
    if (o.friction_angle_deg)
      m.friction_angle = radians(*o.friction_angle_deg);
    else if (group_phi)
    {
      o.friction_angle_deg = group_phi; // as the table writes it, for used_parameters.prm
      m.friction_angle     = radians(*group_phi);
    }
    m.residual_friction_angle = o.residual_friction_angle_deg ? radians(*o.residual_friction_angle_deg) : -1.0;
  }

  double friction_angle_degrees(const sph::MaterialParameters &m) { return degrees(m.friction_angle); }
} // namespace app::keys

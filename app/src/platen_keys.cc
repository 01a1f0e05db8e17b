// Case-file keys of the Platens section: the steel body (fem::Parameters) and the interface and
// geometry settings of coupling::PlatenParameters.
#include "case_keys.h"

namespace app::keys
{
  void declare_platen_keys(Section &s, coupling::CaseParameters &p)
  {
    coupling::PlatenParameters &pl = p.platens;
    fem::Parameters &steel         = pl.steel;
    s.add_enum("Model", steel.model, "rigid|elastic", {fem::SteelModel::rigid, fem::SteelModel::elastic},
               "rigid (prescribed) or elastic steel (FEM)");
    s.add<double>("Friction coefficient", pl.friction, "Coulomb friction rock-platen [-]",
                  [](double v) { return v >= 0 && v <= 2; }, "must be in [0, 2]");
    s.add<double>("Dynamic friction coefficient", pl.dynamic_friction,
                  "sliding friction [-]; -1 = the Friction coefficient (static)",
                  [](double v) { return v == -1 || (v >= 0 && v <= 2); }, "must be -1 (as static) or in [0, 2]");
    s.check("Dynamic friction coefficient", [&pl]() {
      return pl.dynamic_friction <= pl.friction ? std::string()
                                                : "must not exceed the Friction coefficient (static, " +
                                                    format(pl.friction) + ")";
    });
    s.add_enum("Contact method", pl.contact_method, "automatic|penalty|kinematic",
               {coupling::ContactMethod::automatic, coupling::ContactMethod::penalty,
                coupling::ContactMethod::kinematic},
               "kinematic constraint (no stiffness: the step's penetration removed exactly, Coulomb "
               "stick/slip), penalty spring (Contact stiffness scale), or automatic: kinematic for "
               "UCS, BTS and CTCS, penalty for indentation and linear cutting");
    s.check("Contact method", [&p]() {
      if (p.platens.contact_method != coupling::ContactMethod::kinematic)
        return std::string();
      return p.test == "UCS" || p.test == "BTS" || p.test == "CTCS"
               ? std::string()
               : "kinematic is for UCS, BTS and CTCS; " + p.test + " uses penalty";
    });
    s.add_enum("Bonded", pl.bonded, "false|true", {false, true},
               "rock tied to the platen once touched (no slip, no separation; kinematic contact only)");
    s.check("Bonded", [&p]() {
      const coupling::PlatenParameters &pl = p.platens;
      if (!pl.bonded)
        return std::string();
      if (coupling::contact_method(p) != coupling::ContactMethod::kinematic)
        return std::string("needs the kinematic contact (Contact method = kinematic, or automatic for UCS, BTS, CTCS)");
      return pl.friction == 0 ? std::string() : std::string("a bonded interface has no friction; leave Friction coefficient 0");
    });
    s.add<double>("Contact tolerance", pl.contact_tolerance,
                  "kinematic contact on elastic platens: the contacts sharing face nodes are solved together until every end gap is below this fraction of the contact radius [-]",
                  [](double v) { return v > 0 && v <= 1e-2; }, "must be in (0, 0.01]");
    // a setting read by the kinematic contact on elastic platens only: refused elsewhere unless
    // left at its default
    const auto elastic_kinematic_only = [&p](const bool at_default, const std::string &default_value) {
      if (at_default || (coupling::contact_method(p) == coupling::ContactMethod::kinematic &&
                         p.platens.steel.model == fem::SteelModel::elastic))
        return std::string();
      return "is read by the kinematic contact on elastic platens only (Contact method = kinematic or automatic "
             "for UCS, BTS, CTCS, and Model = elastic); leave it at " +
             default_value;
    };
    s.check("Contact tolerance", [&p, elastic_kinematic_only]() {
      return elastic_kinematic_only(p.platens.contact_tolerance == coupling::PlatenParameters().contact_tolerance, "1e-6");
    });
    s.add<int>("Contact patch points", pl.contact_patch_points,
               "kinematic contact on elastic platens: a particle's force is spread over its patch of the face (its cell's end face), sampled at N x N points; 1 = at one point; 0 = 4 for UCS and CTCS, for BTS from the element size h and the spacing dx, ceil((2 dx / h)^2) up to 4 [-]",
               [](int v) { return v >= 0 && v <= 16; }, "must be in [0, 16] (0 = automatic)");
    s.check("Contact patch points", [&p, elastic_kinematic_only]() {
      return elastic_kinematic_only(
        p.platens.contact_patch_points == coupling::PlatenParameters().contact_patch_points, "0");
    });
    s.add<double>("Youngs modulus", steel.youngs_modulus, "[Pa]", [](double v) { return v > 0 && v < 1e13; },
                  "must be in (0, 1e13) Pa");
    s.add<double>("Poissons ratio", steel.poissons_ratio, "[-]", [](double v) { return v >= 0 && v < 0.5; },
                  "must be in [0, 0.5)");
    s.add<double>("Density", steel.density, "[kg/m^3]", [](double v) { return v > 0 && v < 30000; },
                  "must be in (0, 30000) kg/m^3");
    s.add_enum("Loaded face", steel.loaded_face_lateral, "clamped|roller",
               {fem::LoadedFaceLateral::fixed, fem::LoadedFaceLateral::free},
               "elastic platens: the face the ram pushes is clamped (held laterally, a ram bonded to it) "
               "or a roller (free to expand, a lubricated ram: with a platen of the specimen's diameter "
               "and free slip the test is then uniaxial throughout)");
    s.check("Loaded face", [&p]() {
      if (p.platens.steel.loaded_face_lateral == fem::LoadedFaceLateral::fixed)
        return std::string();
      if (p.platens.steel.model != fem::SteelModel::elastic)
        return std::string("is for elastic platens (Model = elastic); a rigid platen has no loaded face of its own");
      // the cutting driver holds its cutter's loaded face (cutting_driver.cc)
      return p.test == "UCS" || p.test == "BTS" || p.test == "CTCS"
               ? std::string()
               : "is for the specimen tests' platens (UCS, BTS, CTCS); " + p.test + " clamps its cutter: leave it clamped";
    });
    s.add<double>("Thickness", pl.thickness, "along the loading axis [m]", [](double v) { return v > 0 && v <= 10; },
                  "must be in (0, 10] m");
    s.add<double>("Diameter", pl.diameter, "diameter (UCS/CTCS) or width (BTS) [m]; 0 = from the specimen: 1.2 D (UCS/CTCS), 0.6 D (BTS)",
                  [](double v) { return v >= 0 && v <= 10; }, "must be in [0, 10] m (0 = from the specimen)");
    // 0 selects the rule (from the particle spacing); another value is the steel's element size
    {
      const std::string doc = "FEM element size [m]; 0 = from the particle spacing";
      s.add_real("Element size", pl.element_size_from_spacing ? "0" : format(steel.element_size),
                 [&pl](double h) {
                   pl.element_size_from_spacing = h == 0;
                   if (h != 0)
                     pl.steel.element_size = h;
                 },
                 doc);
      s.check("Element size", [&pl]() {
        const double h = pl.element_size_from_spacing ? 0.0 : pl.steel.element_size;
        return h >= 0 && h <= pl.thickness ? "" : "must be in [0, platen thickness] m (0 = from the particle spacing)";
      });
    }
    s.add<double>("Contact stiffness scale", pl.contact_stiffness_scale,
                  "penalty stiffness / its stability bound at the rock step [-]; the step shrinks by sqrt(1 + s); 0.5 for stress waves",
                  [](double v) { return v > 0 && v <= 1; }, "must be in (0, 1]");
    s.check("Contact stiffness scale", [&p]() {
      // read by the penalty method only: a value set for a kinematic run would be ignored
      if (coupling::contact_method(p) != coupling::ContactMethod::kinematic ||
          p.platens.contact_stiffness_scale == 0.1)
        return std::string();
      return std::string("is read by the penalty contact only, and ") + p.test +
             " runs the kinematic one: set Contact method = penalty to use it, or leave it at 0.1";
    });
    s.add<double>("Frame stiffness", pl.frame_stiffness,
                  "load frame in series with the top platen [N/m]: the actuator moves at the loading rate, the platen by that minus F / k_frame, and the displacement is read at the actuator; 0 = a rigid frame",
                  [](double v) { return v >= 0 && v < 1e15; }, "must be in [0, 1e15) N/m (0 = a rigid frame; laboratory frames: about 1e8-1e10)");
    s.check("Frame stiffness", [&p]() {
      const coupling::PlatenParameters &pl = p.platens;
      if (pl.frame_stiffness == 0)
        return std::string();
      if (pl.steel.model != fem::SteelModel::rigid)
        return std::string("drives a rigid platen; set Platens/Model = rigid or Frame stiffness = 0");
      if (p.test != "UCS" && p.test != "BTS" && p.test != "CTCS")
        return "is for the specimen tests (UCS, BTS, CTCS); Test/Type = " + p.test + " (set it to 0)";
      return std::string();
    });
    s.add<double>("Frame damping ratio", pl.frame_damping_ratio,
                  "damping ratio zeta of the load frame's dashpot beside its spring, c = 2 zeta sqrt(k_frame m_platen) [-] (used with Frame stiffness > 0); at a steady rate it carries a constant force, which shifts the stroke, not the modulus",
                  [](double v) { return v >= 0 && v <= 10; }, "must be in [0, 10] (1 = critical on the platen's mass)");
    s.check("Frame damping ratio", [&pl]() {
      return pl.frame_stiffness > 0 || pl.frame_damping_ratio == coupling::PlatenParameters().frame_damping_ratio
               ? std::string()
               : "is used with Platens/Frame stiffness > 0 only; leave it at its default (1)";
    });
    s.add_choice("Shape", pl.shape, "flat|jaw", "BTS: flat platens or ISRM curved loading jaws (UCS/CTCS: flat only)",
                 [&p]() {
                   return p.platens.shape == "flat" || p.test == "BTS" ? std::string()
                                                                       : "jaw is for BTS only; use flat for " + p.test;
                 });
    s.add<double>("Jaw radius", pl.jaw_radius, "BTS jaw: radius of the contact arc [m]; 0 = 1.5 x disc radius (ISRM)");
    s.check("Jaw radius", [&p]() {
      const coupling::PlatenParameters &pl = p.platens;
      if (pl.shape != "jaw")
        return pl.jaw_radius == 0 ? std::string() : "is used with Platens/Shape = jaw only; leave it 0";
      const double width  = pl.diameter > 0 ? pl.diameter : 0.6 * p.diameter; // as the driver builds it
      const double radius = pl.jaw_radius > 0 ? pl.jaw_radius : 0.75 * p.diameter;
      return pl.jaw_radius >= 0 && radius > 0.5 * p.diameter && radius > 0.5 * width
               ? std::string()
               : "must exceed the disc radius (" + format(0.5 * p.diameter * 1e3) + " mm) and half the jaw width (" +
                   format(0.5 * width * 1e3) + " mm); ISRM: 1.5 x the disc radius (0 = that)";
    });
  }
} // namespace app::keys

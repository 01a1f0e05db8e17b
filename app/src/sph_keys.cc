// Case-file keys of the SPH section: sph::Parameters (and the loaded-face correction of the
// specimen tests).
#include "case_keys.h"

namespace app::keys
{
  void declare_sph_keys(Section &s, coupling::CaseParameters &p)
  {
    sph::Parameters &n = p.sph;
    s.add<double>("Particle spacing", n.spacing, "lattice spacing dx [m]", [](double v) { return v > 0; },
                  "must be > 0 m (e.g. 0.001 to 0.005)");
    s.add_enum("FORM", n.form, "0|1|7|8",
               {sph::Formulation::updated_lagrangian, sph::Formulation::updated_lagrangian_corrected,
                sph::Formulation::total_lagrangian, sph::Formulation::total_lagrangian_corrected},
               "LS-DYNA formulation: 0/1 updated Lagrangian without/with gradient correction, 7/8 total Lagrangian");
    s.add<double>("CSLH", n.cslh, "smoothing length h = CSLH dx [-]", [](double v) { return v >= 1.0 && v <= 2.0; },
                  "must be in [1.0, 2.0] (the paper tests 1.05, 1.2, 1.3; LS-DYNA default 1.2)");
    s.add<double>("TSSFAC", n.tssfac, "time-step scale factor [-]", [](double v) { return v > 0 && v <= 10; },
                  "must be in (0, 10] (stable: at most 1, usually 0.9)");
    s.add_enum("Kernel", n.kernel, "cubic|wendland", {sph::KernelType::cubic_spline, sph::KernelType::wendland_c2},
               "smoothing kernel");
    s.add("Evolve smoothing length", n.evolve_h, "dh/dt = (h/d) div v");
    s.add<double>("Viscosity alpha", n.av_alpha, "Monaghan artificial viscosity, linear [-]",
                  [](double v) { return v >= 0 && v <= 10; }, "must be in [0, 10]");
    s.add<double>("Viscosity beta", n.av_beta, "Monaghan artificial viscosity, quadratic [-]",
                  [](double v) { return v >= 0 && v <= 10; }, "must be in [0, 10]");
    s.add<double>("Hourglass coefficient", n.hourglass, "total-Lagrangian hourglass control [-]",
                  [](double v) { return v >= 0 && v <= 1; }, "must be in [0, 1]");
    s.add("Hourglass fading", n.hourglass_fade,
          "no hourglass control across cracks: none on a pair once either particle softens in tension");
    s.add("Loaded face correction", p.loaded_face_correction,
          "UCS/CTCS: move the symmetric force's boundary term onto the layer the platen loads");
    s.add_enum("Particle arrangement", p.particle_arrangement, "lattice|body-fitted",
               {sph::ParticleArrangement::lattice, sph::ParticleArrangement::body_fitted},
               "UCS/CTCS cylinder, BTS disc: cell centres of a cubic lattice (staircase round surface) or "
               "body-fitted rings (outer ring half a spacing inside the round surface; a flattened disc's rings "
               "pulled in along their radii onto its flats)");
    s.add<int>("Threads", n.n_threads, "threads of the run (SPH and coupling loops); 0 = all cores",
               [](int v) { return v >= 0 && v <= 4096; }, "must be in [0, 4096] (0 = all cores)");
    s.add_enum("Pair force precision", n.single_precision, "mixed|double", {true, false},
               "3-D pair force on AVX2: float terms with double differences and sums (mixed) or all double");
  }
} // namespace app::keys

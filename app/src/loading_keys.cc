// Case-file keys of the Loading section: the loading path and the quasi-static limits.
#include "case_keys.h"

namespace app::keys
{
  void declare_loading_keys(Section &s, coupling::CaseParameters &p)
  {
    coupling::LoadingParameters &l = p.loading;
    s.add<double>("Strain rate", l.strain_rate, "nominal axial strain rate [1/s]; 0 = from the wave transit time",
                  [](double v) { return v >= 0 && v <= 100; },
                  "must be in [0, 100] 1/s (0 = derived from the wave transit time; the paper uses 0.01)");
    s.add<double>("Transit times", l.transit_times, "derived rate: ramp to peak over this many wave transits [-]",
                  [](double v) { return v > 0 && v <= 1e6; }, "must be in (0, 1e6]");
    s.add<double>("End strain", l.end_strain, "stop at this nominal strain [-] (BTS: displacement / D)",
                  [](double v) { return v > 0 && v <= 0.5; }, "must be in (0, 0.5]");
    s.add<double>("Post-peak drop", l.post_peak_drop, "stop when the load fell this fraction below its peak [-]",
                  [](double v) { return v > 0 && v < 1; }, "must be in (0, 1)");
    s.add<double>("Max kinetic ratio", l.max_kinetic_ratio, "quasi-static limit, kinetic / internal energy [-]",
                  [](double v) { return v > 0; }, "must be > 0");
    s.add<double>("Max force imbalance", l.max_force_imbalance, "quasi-static limit, |F_top - F_bottom| / F [-]",
                  [](double v) { return v > 0; }, "must be > 0");
  }
} // namespace app::keys

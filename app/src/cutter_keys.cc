// Case-file keys of the Cutter section: the indenter or disc cutter, its path, the rock block.
#include "case_keys.h"

namespace app::keys
{
  void declare_cutter_keys(Section &s, coupling::CaseParameters &p)
  {
    coupling::CutterParameters &c = p.cutter;
    s.add_choice("Shape", c.shape, "wedge|cone|flat|disc",
                 "indentation: wedge, cone or flat (cylindrical punch); linear-cutting: disc (CCS disc cutter)");
    s.add<double>("Tip angle", c.tip_angle, "wedge / cone included angle [deg]",
                  [](double v) { return v >= 30 && v <= 170; }, "must be in [30, 170] degrees");
    s.add<double>("Tip radius", c.tip_radius, "wedge / cone tip rounding radius [m]; 0 = sharp",
                  [](double v) { return v >= 0 && v <= 0.1; }, "must be in [0, 0.1] m");
    s.add<double>("Indenter width", c.indenter_width, "wedge width across its tip, cone / punch diameter [m]",
                  [](double v) { return v > 0 && v <= 1; }, "must be in (0, 1] m");
    s.add<double>("Wedge length", c.wedge_length, "wedge tip length along y [m]",
                  [](double v) { return v > 0 && v <= 1; }, "must be in (0, 1] m");
    s.add<double>("Disc diameter", c.disc_diameter, "disc cutter diameter [m] (17 inch: 0.4318)",
                  [](double v) { return v > 0.02 && v <= 1; }, "must be in (0.02, 1] m");
    s.add<double>("Tip width", c.tip_width, "CCS disc tip width [m]", [](double v) { return v > 0 && v <= 0.1; },
                  "must be in (0, 0.1] m");
    s.add<double>("Penetration", c.penetration, "depth of cut (linear-cutting) or final depth (indentation) [m]");
    s.add<double>("Line spacing", c.line_spacing, "spacing between cuts [m], for the CSM estimate (one pass is cut)",
                  [](double v) { return v > 0 && v <= 1; }, "must be in (0, 1] m");
    s.add<double>("Speed", c.speed, "cutting speed along x, indentation speed along -z [m/s]",
                  [](double v) { return v > 0 && v <= 100; }, "must be in (0, 100] m/s");
    s.add<double>("Cut length", c.cut_length, "distance cut along x [m]");
    s.add<double>("Block length", c.block_length, "rock block along the cut (x) [m]",
                  [](double v) { return v > 0 && v <= 2; }, "must be in (0, 2] m");
    s.add<double>("Block width", c.block_width, "rock block across the cut (y) [m]",
                  [](double v) { return v > 0 && v <= 2; }, "must be in (0, 2] m");
    s.add<double>("Block height", c.block_height, "rock block depth (z) [m]",
                  [](double v) { return v > 0 && v <= 2; }, "must be in (0, 2] m");
  }
} // namespace app::keys

// Case-file keys of the Test section: the test and the specimen.
#include "case_keys.h"

namespace app::keys
{
  void declare_test_keys(Section &s, coupling::CaseParameters &p)
  {
    s.add_choice("Type", p.test, "UCS|BTS|CTCS|indentation|linear-cutting",
                 "UCS (cylinder), BTS (disc), CTCS (confined cylinder), indentation, linear-cutting (rock block, Cutter section)");
    s.add("Name", p.name, "case name; empty = the case file's stem");
    s.add<double>("Diameter", p.diameter, "specimen diameter [m]",
                  [](double v) { return v > 0 && v <= 10; }, "must be in (0, 10] m");
    s.add<double>("Length", p.length, "UCS/CTCS specimen length, BTS disc thickness [m]",
                  [](double v) { return v > 0 && v <= 10; }, "must be in (0, 10] m");
    s.add_degrees("Flat loading angle", p.flat_angle,
                  "BTS: loading angle 2 alpha of a flattened Brazilian disc [deg]: two flats 2 R sin(alpha) wide, "
                  "the platens on them, at any particle spacing (the reference study's disc rests on flats of 20 deg); "
                  "0 = the round disc (a lattice disc then rests on flats of its outer rows, wider at coarser spacing; "
                  "a body-fitted one on a line)",
                  [](double v) { return v >= 0 && v <= 60; }, "must be in [0, 60] degrees");
    s.check("Flat loading angle", [&p]() {
      if (p.flat_angle == 0)
        return std::string();
      if (p.test != "BTS")
        return "is for Test/Type = BTS (this case is " + p.test + "); set it to 0";
      if (p.platens.shape != "flat")
        return std::string("needs Platens/Shape = flat (the flats rest on flat platens)");
      return std::string();
    });
    s.add<double>("Confining pressure", p.confining_pressure, "CTCS lateral pressure [Pa], compression positive",
                  [](double v) { return v >= 0 && v < 1e10; },
                  "must be >= 0 Pa (compression positive) and below 1e10 Pa");
    s.check("Confining pressure", [&p]() {
      return p.test == "CTCS" || p.confining_pressure == 0
               ? std::string()
               : "applies only to Test/Type = CTCS (this case is " + p.test + "); set it to 0 or use CTCS";
    });
  }
} // namespace app::keys

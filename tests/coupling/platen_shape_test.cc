// The BTS platen shape in the case file: flat platens or ISRM curved jaws, validated.
#include <app/case_file.h>
#include <coupling/run_case.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace
{
  std::string bts_case()
  {
    return std::string(COSIM_SOURCE_DIR) + "/cases/bts/bts-round.prm";
  }
} // namespace

TEST(BodyShape, BtsDefaultsToFlatAndReadsJaws)
{
  using app::read_case_file;
  EXPECT_EQ(read_case_file(bts_case(), {}).parameters.platens.shape, "flat");
  const auto jaw = read_case_file(bts_case(), {"Platens/Shape=jaw"}).parameters.platens;
  EXPECT_EQ(jaw.shape, "jaw");
  EXPECT_NEAR(jaw.jaw_radius, 0.0, 0.0); // 0 = the ISRM 1.5 disc radii, resolved by the driver
  const auto r =
    read_case_file(bts_case(), {"Platens/Shape=jaw", "Platens/Jaw radius=0.04"}).parameters.platens;
  EXPECT_NEAR(r.jaw_radius, 0.04, 1e-15);
}

TEST(BodyShape, BadShapesAreInputErrors)
{
  using coupling::InputError;
  using app::read_case_file;
  const std::string ucs = std::string(COSIM_SOURCE_DIR) + "/cases/ucs/ucs.prm";
  // jaws are for BTS only
  EXPECT_THROW(read_case_file(ucs, {"Platens/Shape=jaw"}), InputError);
  // a jaw radius below the disc radius (25 mm) would touch the disc at two lines
  EXPECT_THROW(read_case_file(bts_case(), {"Platens/Shape=jaw", "Platens/Jaw radius=0.02"}),
               InputError);
  // a radius with flat platens would be read and ignored
  EXPECT_THROW(read_case_file(bts_case(), {"Platens/Jaw radius=0.04"}), InputError);
  EXPECT_THROW(read_case_file(bts_case(), {"Platens/Shape=round"}), InputError);
}

// `cosim reference` through the built program: bad input (exit 2, one line, nothing written) and
// a tiny elastic run that writes its result folder.
#include "subprocess.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace cosim_test;

namespace
{
  const std::string ucs_case = source("cases/ucs/ucs.prm");

  void expect_refused(const std::vector<std::string> &args, const std::string &fragment)
  {
    Sandbox box;
    const auto before = listing(box.dir());
    const Result r    = run_cosim(box, args);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line only:\n" << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
    EXPECT_EQ(listing(box.dir()), before) << "bad input must write nothing";
  }
} // namespace

TEST(ReferenceCommand, RefusesBadOptions)
{
  expect_refused({"reference"}, "no case file");
  expect_refused({"reference", ucs_case, "--interface", "glued"}, "accepted: bonded, free-slip");
  expect_refused({"reference", ucs_case, "--mesh", "0"}, "--mesh");
  expect_refused({"reference", ucs_case, "--meshes", "4"}, "did you mean '--mesh'");
  expect_refused({"reference", source("cases/bts/bts.prm")}, "UCS cylinder only");
}

TEST(ReferenceCommand, WritesItsResultFolder)
{
  Sandbox box;
  const Result r =
    run_cosim(box, {"reference", ucs_case, "-o", "out", "--set", "Rock/Model=elastic", "--mesh",
                    "2", "--increments", "2", "--end-strain", "0.001", "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const auto *f : {"summary.json", "curve.csv", "end_face_stress.csv", "axis_stress.csv",
                        "used_parameters.prm", ".cosim-result"})
    EXPECT_TRUE(fs::exists(box.dir() / "out" / f)) << f;
  const std::string summary = read_file(box.dir() / "out" / "summary.json");
  EXPECT_NE(summary.find("\"peak_stress_MPa\": 97.07"), std::string::npos)
    << summary; // E x 1e-3, E = 97.07 GPa
  EXPECT_NE(summary.find("\"interface\": \"free-slip\""), std::string::npos);
  const std::string curve = read_file(box.dir() / "out" / "curve.csv");
  EXPECT_EQ(
    curve.rfind(
      "platen_displacement_mm,strain,radial_strain,force_kN,stress_MPa,newton_iterations\n", 0),
    0u);
  EXPECT_EQ(std::count(curve.begin(), curve.end(), '\n'),
            4); // header, unloaded state, 2 increments
  // a second run into the same folder without --force is refused
  const Result again =
    run_cosim(box, {"reference", ucs_case, "-o", "out", "--set", "Rock/Model=elastic"});
  EXPECT_EQ(again.status, 2) << again.err;
}

TEST(ReferenceCommand, HoekBrownRockReachesItsUniaxialClosedForm)
{
  // the shipped case's rock (Hoek-Brown, M1: sigma_ci 282.18 MPa) on rigid free-slip platens:
  // the uniform cylinder's limit load is sigma_ci s^a on any mesh (measured 282.1800044 MPa on 2
  // elements per radius; the digits printed are the closed form's to 1e-5)
  Sandbox box;
  const Result r = run_cosim(box, {"reference", ucs_case, "-o", "out", "--mesh", "2",
                                   "--increments", "40", "--end-strain", "0.004", "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string summary = read_file(box.dir() / "out" / "summary.json");
  EXPECT_NE(summary.find("\"rock_model\": \"hoek-brown\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"closed_form_ucs_MPa\": 282.18"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"peak_stress_MPa\": 282.180"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"mohr_coulomb_ucs_MPa\": null"), std::string::npos) << summary;
}

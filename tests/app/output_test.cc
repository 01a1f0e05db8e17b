// The output writers with made-up data (no run needed): summary.json keys and schema,
// diagnosis.json, history.csv columns, results.h5 + results.xdmf, curve.png, progress lines.
#include <app/output_writer.h>
#include <app/paths.h>
#include <app/progress.h>
#include <diagnose/diagnose.h>

#include <hdf5.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace
{
  std::string read(const fs::path &p)
  {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  struct TempDir
  {
    TempDir()
    {
      std::string pattern = (fs::temp_directory_path() / "cosim-output-test-XXXXXX").string();
      path = mkdtemp(pattern.data());
    }
    ~TempDir() { fs::remove_all(path); }
    fs::path path;
  };
} // namespace

// The keys every summary.json has, whatever the outcome (design.md's, then the run's own).
const char *const summary_keys[] = {
  "schema_version", "status", "cosim_version", "commit", "message", "test", "n_particles", "n_steps",
  "wall_seconds", "peak_stress_MPa", "peak_force_kN", "strain_at_peak", "youngs_modulus_GPa",
  "platen_modulus_GPa", "poissons_ratio", "max_displacement_mm", "max_kinetic_to_internal_energy",
  "max_force_imbalance", "energy_balance_error", "max_exchange_imbalance", "quasi_static", "true_area_mm2",
  "lattice_area_mm2", "strain_rate_per_s", "time_step_s", "stop_reason", "last_good_state", "checkpoint",
  "restart"};

TEST(Output, SummaryJsonHasEveryKeyInPrefixedUnits)
{
  coupling::Summary s;
  s.test = "UCS";
  s.peak_stress = 281.44e6;
  s.peak_force = 552.6e3;
  s.youngs_modulus = 97e9;
  s.max_displacement = 0.3e-3;
  s.poissons_ratio = -1;
  s.max_exchange_imbalance = 7.25e-16;
  s.stop_reason = "end strain";
  const std::string text = app::summary_json(s);
  const auto j = nlohmann::json::parse(text);
  for (const auto *k : summary_keys)
    EXPECT_TRUE(j.contains(k)) << k << " in\n" << text;
  EXPECT_EQ(j.size(), std::size(summary_keys)) << text;
  EXPECT_EQ(j["schema_version"], 1);
  EXPECT_EQ(j["status"], "completed");
  EXPECT_EQ(j["cosim_version"], app::version());
  EXPECT_EQ(j["commit"], app::commit());
  EXPECT_TRUE(j["message"].is_null());
  EXPECT_EQ(j["test"], "UCS");
  // unit conversions rounded to 10 digits: the value as written, not 281.44000000000005
  EXPECT_NE(text.find("\"peak_stress_MPa\": 281.44,"), std::string::npos) << text;
  EXPECT_DOUBLE_EQ(j["peak_force_kN"].get<double>(), 552.6);
  EXPECT_DOUBLE_EQ(j["youngs_modulus_GPa"].get<double>(), 97);
  EXPECT_DOUBLE_EQ(j["max_displacement_mm"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(j["max_exchange_imbalance"].get<double>(), 7.25e-16);
  EXPECT_TRUE(j["poissons_ratio"].is_null()) << "not measured";
  EXPECT_EQ(j["quasi_static"], false);
  EXPECT_EQ(j["stop_reason"], "end strain");
  for (const auto *k : {"last_good_state", "checkpoint", "restart"})
    EXPECT_TRUE(j[k].is_null()) << k;
}

TEST(Output, SummaryJsonWritesTheExtraResultsOfATestType)
{
  coupling::Summary s;
  s.test  = "linear-cutting";
  s.extra = {{"mean_normal_force_kN", 12.5}, {"specific_energy_MJ_m3", std::nan("")}, {"n_sph_pairs", 35260}};
  const std::string text = app::summary_json(s);
  const auto j = nlohmann::json::parse(text); // valid JSON with the extras in it
  EXPECT_DOUBLE_EQ(j["mean_normal_force_kN"].get<double>(), 12.5);
  // no chip, no specific energy: null, not a number JSON cannot hold
  EXPECT_TRUE(j["specific_energy_MJ_m3"].is_null()) << text;
  EXPECT_NE(text.find("\"n_sph_pairs\": 35260\n"), std::string::npos) << "a count stays a whole number: " << text;
  EXPECT_EQ(j.size(), std::size(summary_keys) + 3);
}

// One schema for every outcome: the same keys, null where the outcome has no value.
TEST(Output, SummaryJsonHasTheSameKeysForEveryOutcome)
{
  coupling::Summary s;
  s.test = "UCS";
  s.n_steps = 935;
  app::RunEnd unstable;
  unstable.status         = app::RunStatus::unstable;
  unstable.message        = "step 812: particle 17 moved \"2.1 h\" in one step\n(time step too large)";
  unstable.test           = "UCS";
  unstable.wall_seconds   = 3.5;
  unstable.last_good_step = 800;
  unstable.last_good_time = 6.2e-4;
  app::RunEnd interrupted;
  interrupted.status          = app::RunStatus::interrupted;
  interrupted.message         = "SIGTERM";
  interrupted.test            = "BTS";
  interrupted.n_steps         = 400;
  interrupted.checkpoint      = "checkpoint.h5";
  interrupted.restart_command = "cosim run --restart /tmp/out";
  app::RunEnd failed;
  failed.status = app::RunStatus::failed;

  const auto completed_json   = nlohmann::json::parse(app::summary_json(s));
  const std::string unstable_text = app::summary_json(nullptr, unstable);
  const auto unstable_json    = nlohmann::json::parse(unstable_text);
  const auto interrupted_json = nlohmann::json::parse(app::summary_json(nullptr, interrupted));
  const auto failed_json      = nlohmann::json::parse(app::summary_json(nullptr, failed));
  for (const auto *j : {&completed_json, &unstable_json, &interrupted_json, &failed_json})
  {
    EXPECT_EQ(j->size(), std::size(summary_keys)) << j->dump();
    for (const auto *k : summary_keys)
      EXPECT_TRUE(j->contains(k)) << k << " in " << j->dump();
    EXPECT_EQ((*j)["schema_version"], 1);
  }
  EXPECT_EQ(completed_json["status"], "completed");
  EXPECT_EQ(unstable_json["status"], "unstable");
  EXPECT_EQ(interrupted_json["status"], "interrupted");
  EXPECT_EQ(failed_json["status"], "failed");

  EXPECT_EQ(unstable_json["message"], unstable.message) << "escaped and read back whole";
  EXPECT_EQ(unstable_json["test"], "UCS");
  EXPECT_DOUBLE_EQ(unstable_json["wall_seconds"].get<double>(), 3.5);
  EXPECT_TRUE(unstable_json["n_steps"].is_null());
  EXPECT_TRUE(unstable_json["peak_stress_MPa"].is_null()) << "no Summary: no results";
  EXPECT_TRUE(unstable_json["quasi_static"].is_null());
  EXPECT_EQ(unstable_json["last_good_state"]["file"], "last_good_state.h5");
  EXPECT_EQ(unstable_json["last_good_state"]["step"], 800);
  EXPECT_DOUBLE_EQ(unstable_json["last_good_state"]["time_s"].get<double>(), 6.2e-4);
  // the nested object stays on its key's line, as tools that grep summary.json expect
  EXPECT_NE(unstable_text.find("\"last_good_state\": {\"file\": \"last_good_state.h5\""), std::string::npos)
    << unstable_text;
  EXPECT_TRUE(unstable_json["checkpoint"].is_null());

  EXPECT_EQ(interrupted_json["n_steps"], 400);
  EXPECT_EQ(interrupted_json["checkpoint"], "checkpoint.h5");
  EXPECT_EQ(interrupted_json["restart"], "cosim run --restart /tmp/out");
  EXPECT_TRUE(interrupted_json["last_good_state"].is_null());
  EXPECT_TRUE(interrupted_json["wall_seconds"].is_null()) << "not given: null, not -1";
  EXPECT_EQ(completed_json["n_steps"], 935);
}

// diagnosis.json: the keys design.md lists, valid JSON whatever the notes hold.
TEST(Output, DiagnosisJsonIsValidWithEveryKey)
{
  diagnose::Diagnosis d;
  d.identified = {"tension_cutoff"};
  diagnose::Candidate c;
  c.name       = "tension_cutoff";
  c.reason     = "a \"quoted\" reason\nover two lines";
  c.parameters = {{"T0", "MPa", 14.2, 0.4}};
  c.delta_bic  = std::nan("");
  d.candidates = {c};
  d.baseline.model = "mohr-coulomb";
  d.extended.model = "mohr-coulomb-cutoff";
  d.extended.coupled = {{"strength_rms_MPa", 3.25}};
  d.gain = 2.5;
  d.noise = {{"strength", 4.0}};
  d.notes = {"tab\there"};
  const auto j = nlohmann::json::parse(diagnose::diagnosis_json(d));
  for (const auto *k : {"identified", "candidates", "baseline", "extended", "gain"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_EQ(j["identified"][0], "tension_cutoff");
  EXPECT_EQ(j["candidates"][0]["note"], c.reason);
  EXPECT_TRUE(j["candidates"][0]["evidence"]["delta_bic"].is_null());
  EXPECT_EQ(j["candidates"][0]["parameters"][0]["name"], "T0");
  EXPECT_DOUBLE_EQ(j["candidates"][0]["parameters"][0]["value"].get<double>(), 14.2);
  EXPECT_EQ(j["extended"]["model"], "mohr-coulomb-cutoff");
  EXPECT_DOUBLE_EQ(j["extended"]["coupled_strength_rms_MPa"].get<double>(), 3.25);
  EXPECT_DOUBLE_EQ(j["gain"].get<double>(), 2.5);
  EXPECT_EQ(j["notes"][0], "tab\there");
}

TEST(Output, HistoryCsvColumnsAndUnits)
{
  TempDir dir;
  coupling::HistoryRow row;
  row.time = 1e-3;
  row.displacement = 0.2e-3;
  row.force = 100e3;
  row.stress = 50e6;
  app::write_history_csv((dir.path / "h.csv").string(), {row, row});
  const std::string text = read(dir.path / "h.csv");
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "time_s,displacement_mm,force_kN,force_bottom_kN,stress_MPa,strain,axial_gauge_strain,radial_strain,kinetic_energy_J,"
            "internal_energy_J,dissipated_energy_J,external_work_J,n_failed,rolling_force_kN,side_force_kN");
  EXPECT_NE(text.find("\n0.001,0.2,100,0,50,"), std::string::npos) << text;
}

TEST(Output, ResultsH5AndXdmf)
{
  TempDir dir;
  coupling::ParticleSnapshot p;
  p.n = 2;
  p.position = {0, 0, 0, 1e-3, 0, 0};
  p.stress = std::vector<double>(12, -1e6);
  coupling::MeshSnapshot m;
  m.name = "platen_top";
  m.position = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  m.hexahedra = {0, 1, 2, 3, 4, 5, 6, 7};
  {
    app::ResultsFile results((dir.path / "results.h5").string());
    results.add_snapshot(0.0, p, {m});
    results.add_snapshot(1e-4, p, {m});
    EXPECT_EQ(results.n_snapshots(), 2u);
    results.write_history({coupling::HistoryRow{}});
    results.close((dir.path / "results.xdmf").string());
  }
  const std::string h5 = read(dir.path / "results.h5");
  ASSERT_GT(h5.size(), 8u);
  EXPECT_EQ(h5.substr(0, 8), std::string("\x89HDF\r\n\x1a\n", 8)) << "HDF5 signature";
  const std::string x = read(dir.path / "results.xdmf");
  EXPECT_NE(x.find("CollectionType=\"Temporal\""), std::string::npos);
  EXPECT_NE(x.find("TopologyType=\"Polyvertex\" NumberOfElements=\"2\""), std::string::npos) << x;
  EXPECT_NE(x.find("TopologyType=\"Hexahedron\" NumberOfElements=\"1\""), std::string::npos) << x;
  EXPECT_NE(x.find("results.h5:/snapshots/000001/meshes/platen_top/hexahedra"), std::string::npos) << x;
  EXPECT_NE(x.find("<Time Value=\"0.0001\"/>"), std::string::npos) << x;
}

namespace
{
  /// A string attribute of `object` ("" when absent or not a string).
  std::string string_attribute(hid_t object, const char *name)
  {
    if (H5Aexists(object, name) <= 0)
      return "";
    const hid_t a    = H5Aopen(object, name, H5P_DEFAULT);
    const hid_t type = H5Aget_type(a);
    std::string out;
    if (H5Tget_class(type) == H5T_STRING)
    {
      if (H5Tis_variable_str(type) > 0)
      {
        char *text = nullptr;
        if (H5Aread(a, type, &text) >= 0 && text)
          out = text;
        H5free_memory(text);
      }
      else
      {
        std::string buffer(H5Tget_size(type), '\0');
        if (H5Aread(a, type, buffer.data()) >= 0)
          out = buffer.c_str();
      }
    }
    H5Tclose(type);
    H5Aclose(a);
    return out;
  }

  std::vector<double> read_doubles(hid_t file, const std::string &path)
  {
    const hid_t d = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
    if (d < 0)
      return {};
    const hid_t space = H5Dget_space(d);
    std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
      v.clear();
    H5Sclose(space);
    H5Dclose(d);
    return v;
  }

  herr_t collect_datasets(hid_t, const char *name, const H5O_info_t *info, void *out)
  {
    if (info->type == H5O_TYPE_DATASET)
      static_cast<std::vector<std::string> *>(out)->push_back(name);
    return 0;
  }
} // namespace

// The stress in XDMF's Tensor6 order, the derived fields, a unit on every dataset and the
// program's version and commit on the root.
TEST(Output, ResultsH5StressOrderDerivedFieldsUnitsAndVersion)
{
  TempDir dir;
  coupling::ParticleSnapshot p;
  p.n        = 2;
  p.position = {0, 0, 0, 1e-3, 0, 0};
  // particle 0: xx,yy,zz,yz,xz,xy = 1..6 MPa (every component its own value); particle 1: uniaxial
  p.stress = {1e6, 2e6, 3e6, 4e6, 5e6, 6e6, 0, 0, -100e6, 0, 0, 0};
  p.failure_mode = {1, 3}; // tensile, crushed
  coupling::MeshSnapshot m;
  m.name      = "platen_top";
  m.position  = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  m.hexahedra = {0, 1, 2, 3, 4, 5, 6, 7};
  {
    app::ResultsFile results((dir.path / "results.h5").string());
    results.add_snapshot(0.0, p, {m});
    results.write_history({coupling::HistoryRow{}});
    results.close((dir.path / "results.xdmf").string());
  }
  const hid_t f = H5Fopen((dir.path / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_EQ(string_attribute(f, "cosim_version"), app::version());
  EXPECT_EQ(string_attribute(f, "commit"), app::commit());

  // XDMF Tensor6: xx,xy,xz,yy,yz,zz
  const auto stress = read_doubles(f, "/snapshots/000000/particles/stress");
  const std::vector<double> expected = {1e6, 6e6, 5e6, 2e6, 4e6, 3e6, 0, 0, 0, 0, 0, -100e6};
  ASSERT_EQ(stress.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_EQ(stress[i], expected[i]) << "component " << i % 6 << " of particle " << i / 6; // copied, exact

  // von Mises sqrt(1/2 ((xx-yy)^2 + (yy-zz)^2 + (zz-xx)^2) + 3 (yz^2 + xz^2 + xy^2)): sqrt(1/2 * 6 + 3 * 77)
  // = sqrt(234) MPa for particle 0, |sigma| for the uniaxial one; round-off only
  const auto von_mises = read_doubles(f, "/snapshots/000000/particles/von_mises");
  ASSERT_EQ(von_mises.size(), 2u);
  EXPECT_NEAR(von_mises[0], std::sqrt(234.0) * 1e6, 1e-9 * 1e6);
  EXPECT_NEAR(von_mises[1], 100e6, 1e-9 * 100e6);
  // mean stress, compression positive: -(1 + 2 + 3) / 3 = -2 MPa (tension), 100 / 3 MPa
  const auto mean = read_doubles(f, "/snapshots/000000/particles/mean_stress_compression_positive");
  ASSERT_EQ(mean.size(), 2u);
  EXPECT_NEAR(mean[0], -2e6, 1e-9 * 2e6);
  EXPECT_NEAR(mean[1], 100e6 / 3, 1e-9 * 100e6);

  // every dataset says its unit
  std::vector<std::string> datasets;
  ASSERT_GE(H5Ovisit2(f, H5_INDEX_NAME, H5_ITER_INC, collect_datasets, &datasets, H5O_INFO_BASIC), 0);
  EXPECT_GT(datasets.size(), 20u);
  for (const auto &name : datasets)
  {
    const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    EXPECT_FALSE(string_attribute(d, "units").empty()) << name << " has no units attribute";
    H5Dclose(d);
  }
  auto units = [&](const char *name) {
    const hid_t d     = H5Dopen2(f, name, H5P_DEFAULT);
    std::string u     = string_attribute(d, "units");
    H5Dclose(d);
    return u;
  };
  EXPECT_EQ(units("/snapshots/000000/particles/stress"), "Pa");
  EXPECT_EQ(units("/snapshots/000000/particles/velocity"), "m/s");
  EXPECT_EQ(units("/history/force_kN"), "kN");
  EXPECT_EQ(units("/history/strain"), "1");
  const hid_t d = H5Dopen2(f, "/snapshots/000000/particles/stress", H5P_DEFAULT);
  EXPECT_EQ(string_attribute(d, "components"), "xx,xy,xz,yy,yz,zz");
  H5Dclose(d);
  // the failure mode: integers, their meaning on the dataset
  {
    const hid_t fm = H5Dopen2(f, "/snapshots/000000/particles/failure_mode", H5P_DEFAULT);
    ASSERT_GE(fm, 0) << "no failure_mode dataset";
    const hid_t type = H5Dget_type(fm);
    EXPECT_EQ(H5Tget_class(type), H5T_INTEGER);
    H5Tclose(type);
    int values[2] = {-1, -1};
    ASSERT_GE(H5Dread(fm, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), 0);
    EXPECT_EQ(values[0], 1);
    EXPECT_EQ(values[1], 3);
    const std::string meaning = string_attribute(fm, "meaning");
    for (const char *word : {"0 none", "1 tensile", "2 shear", "3 crushed"})
      EXPECT_NE(meaning.find(word), std::string::npos) << meaning;
    H5Dclose(fm);
  }
  H5Fclose(f);

  // the XDMF: the stress as Tensor6, the derived fields as scalars, an explicit Polyvertex
  const std::string x = read(dir.path / "results.xdmf");
  EXPECT_NE(x.find("AttributeType=\"Tensor6\" Center=\"Node\"><DataItem Dimensions=\"2 6\""), std::string::npos) << x;
  EXPECT_NE(x.find("<Attribute Name=\"von_mises\" AttributeType=\"Scalar\" Center=\"Node\">"), std::string::npos) << x;
  EXPECT_NE(x.find("<Attribute Name=\"mean_stress_compression_positive\" AttributeType=\"Scalar\""), std::string::npos)
    << x;
  EXPECT_NE(
    x.find("<Attribute Name=\"failure_mode\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem "
           "Dimensions=\"2\" NumberType=\"Int\" Precision=\"4\""),
    std::string::npos)
    << x;
  EXPECT_NE(x.find("NodesPerElement=\"1\"><DataItem Dimensions=\"2\" NumberType=\"UInt\" Precision=\"4\" "
                   "Format=\"HDF\">results.h5:/particle_vertices/2</DataItem></Topology>"),
            std::string::npos)
    << x;
}

// curve.png with the group's measured values and without them (the script must work both ways).
TEST(Output, CurvePlotWithAndWithoutMeasuredValues)
{
  app::CurveLabels labels;
  labels.group                   = "M1";
  labels.particle_spacing        = 2.5e-3;
  labels.measured_ucs            = 282.18e6;
  labels.measured_youngs_modulus = 97.07e9;
  labels.source                  = "Table 3";
  const std::vector<std::string> args = app::curve_label_arguments(labels);
  const std::vector<std::string> expected = {"--group", "M1", "--spacing-mm", "2.5", "--ucs-MPa", "282.18",
                                             "--E-GPa", "97.07", "--source", "Table 3"};
  EXPECT_EQ(args, expected);
  EXPECT_TRUE(app::curve_label_arguments(app::CurveLabels{}).empty());

  TempDir dir;
  std::vector<coupling::HistoryRow> rows;
  for (int i = 0; i <= 20; ++i)
  {
    coupling::HistoryRow r;
    r.time               = i * 1e-5;
    r.strain             = i * 1e-4;
    r.axial_gauge_strain = 0.9 * r.strain;
    r.radial_strain      = 0.25 * r.axial_gauge_strain;
    r.stress             = 97e9 * r.axial_gauge_strain;
    r.displacement       = r.strain * 0.1;
    r.force              = r.stress * 1.96e-3;
    rows.push_back(r);
  }
  const std::string csv = (dir.path / "history.csv").string();
  app::write_history_csv(csv, rows);
  const std::string with = (dir.path / "with.png").string(), without = (dir.path / "without.png").string();
  const std::string why = app::plot_curve(csv, "UCS", with, labels);
  if (why.find("not installed") != std::string::npos || why.find("not found") != std::string::npos)
    GTEST_SKIP() << why;
  EXPECT_EQ(why, "");
  EXPECT_TRUE(fs::exists(with));
  EXPECT_EQ(app::plot_curve(csv, "UCS", without), "");
  EXPECT_TRUE(fs::exists(without));
  app::CurveLabels bts;
  bts.group        = "M1";
  bts.measured_bts = 15.43e6;
  EXPECT_EQ(app::plot_curve(csv, "BTS", (dir.path / "bts.png").string(), bts), "");
  EXPECT_EQ(app::plot_curve(csv, "BTS", (dir.path / "bts_plain.png").string()), "");
}

TEST(Output, ResultsFileRefusesAnUnwritablePath)
{
  EXPECT_THROW(app::ResultsFile("/nonexistent/folder/results.h5"), std::runtime_error);
}

TEST(Progress, LineHasStepTimePercentWallAndTimeLeft)
{
  const std::string line = app::ProgressDisplay::format(1200, 2.5e-3, 0.25, 30.0);
  EXPECT_NE(line.find("step 1200"), std::string::npos) << line;
  EXPECT_NE(line.find("t = 0.0025 s"), std::string::npos) << line;
  EXPECT_NE(line.find("25.0 %"), std::string::npos) << line;
  EXPECT_NE(line.find("wall 00:30"), std::string::npos) << line;
  EXPECT_NE(line.find("left 01:30"), std::string::npos) << line; // 30 s for 25 % -> 90 s to go
}

TEST(Progress, PlainLinesWhenNotATerminalAndSilentWhenQuiet)
{
  TempDir dir;
  const auto path = dir.path / "progress.txt";
  {
    std::FILE *f = std::fopen(path.c_str(), "w");
    app::ProgressDisplay plain(true, f, false, 0.0); // every update prints
    plain.update(1, 0.1, 0.1);
    plain.update(2, 0.2, 0.2);
    plain.finish();
    app::ProgressDisplay quiet(false, f, false, 0.0);
    quiet.update(3, 0.3, 0.3);
    quiet.finish();
    std::fclose(f);
  }
  const std::string text = read(path);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3) << text;
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_EQ(text.find("step 3"), std::string::npos);
}

// The output writers with made-up data (no run needed): summary.json keys, history.csv columns,
// results.h5 + results.xdmf, progress lines.
#include <app/output_writer.h>
#include <app/progress.h>

#include <gtest/gtest.h>

#include <cmath>

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
  const std::string j = app::summary_json(s);
  for (const auto *k : {"test", "n_particles", "n_steps", "wall_seconds", "peak_stress_MPa", "peak_force_kN",
                        "strain_at_peak", "youngs_modulus_GPa", "poissons_ratio", "max_displacement_mm",
                        "max_kinetic_to_internal_energy", "max_force_imbalance", "energy_balance_error",
                        "max_exchange_imbalance", "quasi_static", "true_area_mm2", "lattice_area_mm2", "strain_rate_per_s", "time_step_s",
                        "stop_reason"})
    EXPECT_NE(j.find(std::string("\"") + k + "\": "), std::string::npos) << k;
  EXPECT_NE(j.find("\"peak_stress_MPa\": 281.44,"), std::string::npos) << j;
  EXPECT_NE(j.find("\"peak_force_kN\": 552.6,"), std::string::npos) << j;
  EXPECT_NE(j.find("\"youngs_modulus_GPa\": 97,"), std::string::npos) << j;
  EXPECT_NE(j.find("\"poissons_ratio\": null"), std::string::npos) << j;
  EXPECT_NE(j.find("\"quasi_static\": false"), std::string::npos) << j;
  EXPECT_NE(j.find("\"max_exchange_imbalance\": 7.25e-16,"), std::string::npos) << j;
}

TEST(Output, SummaryJsonWritesTheExtraResultsOfATestType)
{
  coupling::Summary s;
  s.test  = "linear-cutting";
  s.extra = {{"mean_normal_force_kN", 12.5}, {"specific_energy_MJ_m3", std::nan("")}};
  const std::string j = app::summary_json(s);
  EXPECT_NE(j.find("\"mean_normal_force_kN\": 12.5,"), std::string::npos) << j;
  // no chip, no specific energy: null, not a number JSON cannot hold
  EXPECT_NE(j.find("\"specific_energy_MJ_m3\": null,"), std::string::npos) << j;
  EXPECT_NE(j.find("\"stop_reason\": "), std::string::npos) << j; // still the last key, valid JSON
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

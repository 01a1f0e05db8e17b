#pragma once
/// @file
/// Rock material groups (M1..M10 of the reference study) read from a data folder holding
/// table3_fitted_parameters.csv (E, nu, measured c and phi where known, UCS, BTS) and
/// table4_calibrated.csv (c and phi back-calculated from UCS and BTS) and
/// simulator_calibrated.csv (c and phi with which the simulator reproduces UCS and BTS). Units
/// here are SI.

#include <diagnose/calibrate.h>

#include <optional>
#include <string>
#include <vector>

namespace diagnose
{
  /// One material group.
  struct MaterialGroup
  {
    std::string group;                             ///< e.g. "M1"
    std::string source;                            ///< "file:line" of its Table 3 row
    double youngs_modulus = 0;                     ///< [Pa]
    double poissons_ratio = 0;                     ///< [-]
    double ucs = 0;                                ///< fitted uniaxial compressive strength [Pa]
    double bts = 0;                                ///< fitted Brazilian tensile strength [Pa]
    std::optional<double> measured_cohesion;       ///< from CTCS (Table 3) [Pa]
    std::optional<double> measured_friction_angle; ///< from CTCS (Table 3) [deg]
    std::optional<double> calibrated_cohesion;     ///< Table 4 [Pa]
    std::optional<double> calibrated_friction_angle; ///< Table 4 [deg]
    std::optional<double> simulated_cohesion;      ///< simulator_calibrated.csv [Pa]
    std::optional<double> simulated_friction_angle; ///< simulator_calibrated.csv [deg]
    /// simulator_calibrated.csv, optional column: the tension cut-off with which the group's
    /// Hoek-Brown envelope (calibrate --envelope) gives its BTS in the simulator [Pa]
    std::optional<double> simulated_cutoff;
    /// simulator_calibrated.csv, optional column mb: for a group without triaxial data, the m_b
    /// with which a Hoek-Brown envelope of a = 1/2 through its UCS, with no cut-off but its own
    /// tensile apex, gives its BTS in the simulator [-]
    std::optional<double> simulated_mb;
  };

  /// The groups of one data folder.
  class MaterialTable
  {
  public:
    /// Reads `directory`/table3_fitted_parameters.csv and, if present,
    /// `directory`/table4_calibrated.csv and `directory`/simulator_calibrated.csv; checks every
    /// row. Throws InputError with file:line.
    static MaterialTable read(const std::string &directory);

    /// The group named `name`; InputError listing the known groups when there is none.
    const MaterialGroup &find(const std::string &name) const;
    /// Nullptr when there is no such group.
    const MaterialGroup *lookup(const std::string &name) const;
    /// All groups in file order.
    const std::vector<MaterialGroup> &groups() const { return groups_; }
    /// Names of the groups with measured c and phi, comma separated ("M8, M9, M10").
    std::string groups_with_measured_strength() const;
    /// Names of all groups, comma separated.
    std::string group_names() const;

  private:
    /// A table of c_MPa, phi_deg per group at `path`, if it exists, into the two members, and
    /// optional columns cutoff_MPa and mb (empty cells allowed) into `cutoff` and `mb` where
    /// those are given.
    void read_c_phi(const std::string &path, std::optional<double> MaterialGroup::*cohesion,
                    std::optional<double> MaterialGroup::*friction_angle,
                    std::optional<double> MaterialGroup::*cutoff = nullptr,
                    std::optional<double> MaterialGroup::*mb     = nullptr);

    std::vector<MaterialGroup> groups_;
  };

  /// The triaxial strengths of a group: its measured Mohr-Coulomb envelope (Table 3's c, phi) at
  /// Table 1's confining pressures 10, 30 and 50 MPa [Pa]; none where it has no measured c, phi.
  std::vector<TriaxialStrength> triaxial_strengths(const MaterialGroup &group);
} // namespace diagnose

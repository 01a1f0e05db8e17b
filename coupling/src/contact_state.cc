/// @file
/// PenaltyContact::save_state / load_state: the friction history and energy accounts of a contact
/// as named flat arrays, for checkpoints. Hits and per-particle forces are recomputed by every
/// apply() and are not state.

#include <coupling/contact.h>

#include <stdexcept>

namespace coupling
{
  void PenaltyContact::save_state(std::map<std::string, std::vector<double>> &out,
                                  const std::string &prefix) const
  {
    std::vector<double> spring(3 * friction_.size()), sliding(friction_.size()), tied(friction_.size());
    for (std::size_t i = 0; i < friction_.size(); ++i)
    {
      for (int d = 0; d < 3; ++d)
        spring[3 * i + d] = friction_[i].tangential_force[d];
      sliding[i] = friction_[i].sliding ? 1.0 : 0.0;
      tied[i]    = friction_[i].tied ? 1.0 : 0.0;
    }
    out[prefix + "tied"]             = std::move(tied);
    out[prefix + "tangential_force"] = std::move(spring);
    out[prefix + "sliding"]          = std::move(sliding);
    out[prefix + "scalars"]          = {normal_force_, penalty_energy_, friction_dissipation_,
                                        static_cast<double>(n_sliding_)};
  }

  void PenaltyContact::load_state(const std::map<std::string, std::vector<double>> &in,
                                  const std::string &prefix)
  {
    auto find = [&](const std::string &name, std::size_t size) -> const std::vector<double> & {
      const auto it = in.find(prefix + name);
      if (it == in.end() || it->second.size() != size)
        throw std::invalid_argument("contact state: array '" + prefix + name +
                                    (it == in.end() ? "' missing" : "' has the wrong size") +
                                    " (a checkpoint of another case?)");
      return it->second;
    };
    const auto &spring  = find("tangential_force", 3 * friction_.size());
    const auto &sliding = find("sliding", friction_.size());
    for (std::size_t i = 0; i < friction_.size(); ++i)
    {
      for (int d = 0; d < 3; ++d)
        friction_[i].tangential_force[d] = spring[3 * i + d];
      friction_[i].sliding = sliding[i] != 0.0;
    }
    // a bonded interface's ties; absent from checkpoints of versions before bonded interfaces,
    // which had none
    if (in.count(prefix + "tied"))
    {
      const auto &tied = find("tied", friction_.size());
      for (std::size_t i = 0; i < friction_.size(); ++i)
        friction_[i].tied = tied[i] != 0.0;
    }
    const auto &s         = find("scalars", 4);
    normal_force_         = s[0];
    penalty_energy_       = s[1];
    friction_dissipation_ = s[2];
    n_sliding_            = static_cast<std::size_t>(s[3]);
  }
} // namespace coupling

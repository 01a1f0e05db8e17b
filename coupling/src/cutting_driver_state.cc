/// @file
/// CuttingDriver::save_state / load_state: the state of an indentation or linear-cutting run as
/// named flat arrays (checkpoint.h5, `cosim run --restart`). The block, the cutter and the contact
/// save their own; the driver adds its clocks, accounts, history and the chip flags. Per-step
/// scratch (hits, the cutter's contact forces) is recomputed by every step and is not state; the
/// particles' contact forces of the last step are, because the chip release reads them first.
/// A distributed run writes the whole block in global order and its accounts summed over the
/// ranks (as the laboratory driver does), so that its checkpoint continues on any number of ranks.

#include "cutting_driver.h"
#include "driver_common.h"

#include <coupling/run_case.h>

#include <fem/steel_body.h>
#include <sph/body.h>
#include <sph/domain.h>

#include <sstream>
#include <stdexcept>

namespace coupling
{
  namespace
  {
    constexpr std::size_t n_scalars = 16;

  } // namespace

  void CuttingDriver::save_state(StateArrays &out) const
  {
    save_rock_state(*body_, domain_.get(), {{"contact.", contact_.get()}}, out, &state_rows_);
    cutter_->save_state(out, "cutter.");
    // the accounts of this rank's particles: of all ranks
    std::vector<double> mine = {support_impulse_z_, static_cast<double>(n_in_contact_),
                                static_cast<double>(n_released_), released_energy_};
    if (domain_)
      mine = domain_->sum(mine);
    out["driver.scalars"] = {
      time_,
      static_cast<double>(n_steps_),
      frame_work_,
      dt_,
      static_cast<double>(n_substeps_),
      static_cast<double>(domain_ ? domain_->n_global() : body_->n_particles()),
      travel_,
      depth_,
      impulse_[0],
      impulse_[1],
      impulse_[2],
      mine[0],
      impulse_time_,
      mine[1],
      mine[2],
      mine[3]};
    const std::vector<double> released(released_.begin(), released_.end());
    out["driver.released"]      = released; // (distributed: of the owned particles)
    out["driver.contact_force"] = force_on_particles_;
    if (domain_)
    {
      state_rows_.width["driver.released"]      = 1;
      state_rows_.width["driver.contact_force"] = 3;
    }
  }

  void CuttingDriver::load_state(const StateArrays &in)
  {
    auto find = [&](const std::string &name) -> const std::vector<double> & {
      const auto it = in.find(name);
      if (it == in.end())
        throw InputError("checkpoint: no " + name +
                         "; not a checkpoint of an indentation or "
                         "linear-cutting run");
      return it->second;
    };
    const auto &d = find("driver.scalars");
    if (d.size() != n_scalars)
      throw InputError("checkpoint: driver.scalars of another layout; not a checkpoint of an "
                       "indentation or linear-cutting run of this cosim");
    // the same case gives the same particle count, time step and sub-cycling, bit for bit
    const std::size_t n_all = domain_ ? domain_->n_global() : body_->n_particles();
    if (d[5] != n_all || d[3] != dt_ || d[4] != n_substeps_)
    {
      std::ostringstream os;
      os << "checkpoint: it holds " << d[5] << " particles at dt = " << d[3] << " s, this case has "
         << n_all << " at dt = " << dt_ << " s; restart with the case's own used_parameters.prm";
      throw InputError(os.str());
    }
    const auto &all_released = find("driver.released"), &all_force = find("driver.contact_force");
    if (all_released.size() != n_all || all_force.size() != 3 * n_all)
      throw InputError(
        "checkpoint: driver arrays of the wrong size (a checkpoint of another case?)");
    // distributed: the owned particles' rows, the accounts of all ranks on rank 0
    const std::vector<double> released =
      domain_ ? owned_rows(*domain_, all_released, 1) : all_released;
    const std::vector<double> force = domain_ ? owned_rows(*domain_, all_force, 3) : all_force;
    const double share              = domain_ && domain_->rank() != 0 ? 0.0 : 1.0;
    try
    {
      load_rock_state(*body_, domain_.get(), {{"contact.", contact_.get()}}, in);
      cutter_->load_state(in, "cutter.");
    }
    catch (const std::invalid_argument &e)
    {
      throw InputError(std::string("checkpoint: ") + e.what());
    }
    time_              = d[0];
    n_steps_           = static_cast<std::size_t>(d[1]);
    frame_work_        = d[2];
    travel_            = d[6];
    depth_             = d[7];
    impulse_           = {{d[8], d[9], d[10]}};
    support_impulse_z_  = share * d[11];
    impulse_time_      = d[12];
    n_in_contact_       = static_cast<std::size_t>(share * d[13]);
    n_released_         = static_cast<std::size_t>(share * d[14]);
    released_energy_    = share * d[15];
    force_on_particles_ = force;
    // the chip: released particles stay out of the contact (their stiffness factor 0)
    bool any = false;
    for (std::size_t i = 0; i < released_.size(); ++i)
    {
      released_[i] = released[i] != 0.0 ? 1 : 0;
      any          = any || released_[i];
    }
    if (any)
      exclude_released();
  }
} // namespace coupling

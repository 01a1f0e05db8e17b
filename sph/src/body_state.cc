/// @file
/// Body<dim>::save_state / load_state: the run-time state of a body as named flat arrays, for
/// checkpoints. Kept apart from body.cc so that the solver and its serialisation change
/// independently; a field added to Body that changes during a run must be added here too, to
/// for_each_state_field unless it needs a conversion (the restart tests, which compare a restarted
/// history with an uninterrupted one bitwise, fail otherwise).
///
/// Layout: per-particle Eigen vectors and tensors as their `data()` order (column-major), one
/// particle after the other; scalars as arrays of one.

#include <sph/body.h>

#include <algorithm>
#include <stdexcept>

namespace sph
{
  namespace
  {
    template <typename T>
    void pack(StateArrays &out, const std::string &name, const std::vector<T> &values)
    {
      constexpr int k = T::SizeAtCompileTime;
      std::vector<double> a(values.size() * k);
      for (std::size_t i = 0; i < values.size(); ++i)
        std::copy(values[i].data(), values[i].data() + k, a.begin() + i * k);
      out[name] = std::move(a);
    }

    void pack(StateArrays &out, const std::string &name, const std::vector<double> &values)
    {
      out[name] = values;
    }

    const std::vector<double> &find(const StateArrays &in, const std::string &name,
                                    std::size_t size)
    {
      const auto it = in.find(name);
      if (it == in.end())
        throw std::invalid_argument("body state: no array '" + name + "'");
      if (it->second.size() != size)
        throw std::invalid_argument("body state: array '" + name + "' has " +
                                    std::to_string(it->second.size()) + " values, expected " +
                                    std::to_string(size) + " (a checkpoint of another case?)");
      return it->second;
    }

    template <typename T>
    void unpack(const StateArrays &in, const std::string &name, std::vector<T> &values)
    {
      constexpr int k              = T::SizeAtCompileTime;
      const std::vector<double> &a = find(in, name, values.size() * k);
      for (std::size_t i = 0; i < values.size(); ++i)
        std::copy(a.begin() + i * k, a.begin() + (i + 1) * k, values[i].data());
    }

    void unpack(const StateArrays &in, const std::string &name, std::vector<double> &values)
    {
      const std::vector<double> &a = find(in, name, values.size());
      values                       = a;
    }

    void pack(StateArrays &out, const std::string &name, const double value)
    {
      out[name] = {value};
    }

    void unpack(const StateArrays &in, const std::string &name, double &value)
    {
      value = find(in, name, 1)[0];
    }
  } // namespace

  template <int dim>
  template <typename Self, typename F>
  void Body<dim>::for_each_state_field(Self &self, const std::string &prefix, F &&f)
  {
    f(prefix + "x", self.p_.x);
    f(prefix + "v", self.p_.v);
    f(prefix + "volume", self.p_.volume);
    f(prefix + "density", self.p_.density);
    f(prefix + "h", self.p_.h);
    f(prefix + "stress", self.p_.stress);
    f(prefix + "F", self.p_.F);
    f(prefix + "L", self.p_.L);
    f(prefix + "f_int", self.p_.f_int);
    f(prefix + "f_ext", self.p_.f_ext);
    f(prefix + "f_pressure", self.p_.f_pressure);
    f(prefix + "prescribed", self.prescribed_);
    f(prefix + "reaction", self.reaction_);
    f(prefix + "stress_work", self.stress_work_);
    f(prefix + "Q", self.Q_);
    f(prefix + "F_prev", self.F_prev_);
    f(prefix + "pressure", self.pressure_);
    f(prefix + "dt_last", self.dt_last_);
    f(prefix + "viscous", self.viscous_);
    f(prefix + "hourglass", self.hourglass_);
    f(prefix + "external", self.external_);
  }

  template <int dim>
  void Body<dim>::save_state(StateArrays &out, const std::string &prefix) const
  {
    for_each_state_field(*this, prefix,
                         [&out](const std::string &name, const auto &field) { pack(out, name, field); });
    const std::size_t   n = p_.size();
    std::vector<double> plastic(n), damage(n), mode(n), cracked(n), constrained(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      plastic[i]     = p_.history[i].plastic_strain;
      damage[i]      = p_.history[i].damage;
      mode[i]        = static_cast<double>(p_.history[i].failure_mode);
      cracked[i]     = p_.history[i].cracked ? 1.0 : 0.0;
      constrained[i] = constrained_[i];
    }
    out[prefix + "plastic_strain"] = std::move(plastic);
    out[prefix + "damage"]         = std::move(damage);
    out[prefix + "failure_mode"]   = std::move(mode);
    out[prefix + "cracked"]        = std::move(cracked);
    out[prefix + "constrained"]    = std::move(constrained);
  }

  template <int dim>
  void Body<dim>::load_state(const StateArrays &in, const std::string &prefix)
  {
    for_each_state_field(*this, prefix,
                         [&in](const std::string &name, auto &field) { unpack(in, name, field); });
    const std::size_t n       = p_.size();
    const auto       &plastic = find(in, prefix + "plastic_strain", n);
    const auto       &damage  = find(in, prefix + "damage", n);
    const auto       &mode    = find(in, prefix + "failure_mode", n);
    const auto       &cracked = find(in, prefix + "cracked", n);
    const auto       &constr  = find(in, prefix + "constrained", n);
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!(mode[i] >= 0 && mode[i] <= 3))
        throw std::invalid_argument("body state: '" + prefix + "failure_mode' holds " +
                                    std::to_string(mode[i]) + ", expected 0-3");
      p_.history[i].plastic_strain = plastic[i];
      p_.history[i].damage         = damage[i];
      p_.history[i].failure_mode   = static_cast<FailureMode>(static_cast<int>(mode[i]));
      p_.history[i].cracked        = cracked[i] != 0;
      constrained_[i]              = static_cast<std::uint8_t>(constr[i]);
    }
    // the hourglass factors of the loaded cracks, faded afresh in the next force pass
    if (!hg_faded_.empty())
      {
        for (std::size_t p = 0; p < pairs_.n_pairs(); ++p)
          set_hourglass_factor(p, intact_hourglass_factor(p));
        std::fill(hg_faded_.begin(), hg_faded_.end(), 0);
      }
  }

  template class Body<2>;
  template class Body<3>;
} // namespace sph

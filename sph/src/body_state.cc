/// @file
/// Body<dim>::save_state / load_state: the run-time state of a body as named flat arrays, for
/// checkpoints. Kept apart from body.cc so that the solver and its serialisation change
/// independently; a field added to Body that changes during a run must be added here too (the
/// restart test, which compares a restarted history with an uninterrupted one bitwise, fails
/// otherwise).
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

    double scalar(const StateArrays &in, const std::string &name)
    {
      return find(in, name, 1)[0];
    }
  } // namespace

  template <int dim>
  void Body<dim>::save_state(StateArrays &out, const std::string &prefix) const
  {
    const std::size_t n = p_.size();
    pack(out, prefix + "x", p_.x);
    pack(out, prefix + "v", p_.v);
    pack(out, prefix + "volume", p_.volume);
    pack(out, prefix + "density", p_.density);
    pack(out, prefix + "h", p_.h);
    pack(out, prefix + "stress", p_.stress);
    pack(out, prefix + "F", p_.F);
    pack(out, prefix + "L", p_.L);
    pack(out, prefix + "f_int", p_.f_int);
    pack(out, prefix + "f_ext", p_.f_ext);
    pack(out, prefix + "f_pressure", p_.f_pressure);
    std::vector<double> plastic(n), damage(n), constrained(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      plastic[i]     = p_.history[i].plastic_strain;
      damage[i]      = p_.history[i].damage;
      constrained[i] = constrained_[i];
    }
    out[prefix + "plastic_strain"] = std::move(plastic);
    out[prefix + "damage"]         = std::move(damage);
    out[prefix + "constrained"]    = std::move(constrained);
    pack(out, prefix + "prescribed", prescribed_);
    pack(out, prefix + "reaction", reaction_);
    pack(out, prefix + "stress_work", stress_work_);
    pack(out, prefix + "Q", Q_);
    pack(out, prefix + "F_prev", F_prev_);
    out[prefix + "pressure"]  = {pressure_};
    out[prefix + "dt_last"]   = {dt_last_};
    out[prefix + "viscous"]   = {viscous_};
    out[prefix + "hourglass"] = {hourglass_};
    out[prefix + "external"]  = {external_};
  }

  template <int dim>
  void Body<dim>::load_state(const StateArrays &in, const std::string &prefix)
  {
    const std::size_t n = p_.size();
    unpack(in, prefix + "x", p_.x);
    unpack(in, prefix + "v", p_.v);
    unpack(in, prefix + "volume", p_.volume);
    unpack(in, prefix + "density", p_.density);
    unpack(in, prefix + "h", p_.h);
    unpack(in, prefix + "stress", p_.stress);
    unpack(in, prefix + "F", p_.F);
    unpack(in, prefix + "L", p_.L);
    unpack(in, prefix + "f_int", p_.f_int);
    unpack(in, prefix + "f_ext", p_.f_ext);
    unpack(in, prefix + "f_pressure", p_.f_pressure);
    const auto &plastic = find(in, prefix + "plastic_strain", n);
    const auto &damage  = find(in, prefix + "damage", n);
    const auto &constr  = find(in, prefix + "constrained", n);
    for (std::size_t i = 0; i < n; ++i)
    {
      p_.history[i].plastic_strain = plastic[i];
      p_.history[i].damage         = damage[i];
      constrained_[i]              = static_cast<std::uint8_t>(constr[i]);
    }
    unpack(in, prefix + "prescribed", prescribed_);
    unpack(in, prefix + "reaction", reaction_);
    unpack(in, prefix + "stress_work", stress_work_);
    unpack(in, prefix + "Q", Q_);
    unpack(in, prefix + "F_prev", F_prev_);
    pressure_  = scalar(in, prefix + "pressure");
    dt_last_   = scalar(in, prefix + "dt_last");
    viscous_   = scalar(in, prefix + "viscous");
    hourglass_ = scalar(in, prefix + "hourglass");
    external_  = scalar(in, prefix + "external");
  }

  template class Body<2>;
  template class Body<3>;
} // namespace sph

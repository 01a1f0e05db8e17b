#include <sph/domain.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

namespace sph
{
  namespace
  {
    // adds the wall-clock time of its scope to a total [s]
    class Stopwatch
    {
    public:
      explicit Stopwatch(double &total)
          : total_(total)
          , start_(std::chrono::steady_clock::now())
      {}
      ~Stopwatch()
      {
        total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
      }
      Stopwatch(const Stopwatch &)            = delete;
      Stopwatch &operator=(const Stopwatch &) = delete;

    private:
      double                               &total_;
      std::chrono::steady_clock::time_point start_;
    };

    template <int dim>
    void bisect(const std::vector<Vector<dim>> &x, std::vector<std::int32_t> &ids,
                const std::size_t begin, const std::size_t end, const int first_part,
                const int n_parts, std::vector<int> &owners)
    {
      if (n_parts <= 1 || end - begin <= 1)
        {
          for (std::size_t k = begin; k < end; ++k)
            owners[ids[k]] = first_part;
          return;
        }
      Vector<dim> lo = x[ids[begin]], hi = lo;
      for (std::size_t k = begin; k < end; ++k)
        {
          lo = lo.cwiseMin(x[ids[k]]);
          hi = hi.cwiseMax(x[ids[k]]);
        }
      int axis = 0;
      for (int d = 1; d < dim; ++d)
        if (hi[d] - lo[d] > hi[axis] - lo[axis])
          axis = d;
      std::sort(ids.begin() + begin, ids.begin() + end,
                [&](const std::int32_t a, const std::int32_t b) {
                  return x[a][axis] < x[b][axis] || (x[a][axis] == x[b][axis] && a < b);
                });
      const int         left  = n_parts / 2;
      const std::size_t n     = end - begin;
      const std::size_t cut   = begin + n * static_cast<std::size_t>(left) / n_parts;
      bisect(x, ids, begin, cut, first_part, left, owners);
      bisect(x, ids, cut, end, first_part + left, n_parts - left, owners);
    }

    void check(const int status, const char *what)
    {
      if (status != MPI_SUCCESS)
        throw std::runtime_error(std::string("sph::Domain: MPI error in ") + what);
    }
  } // namespace

  template <int dim>
  std::vector<int> bisection_owners(const std::vector<Vector<dim>> &x, const int n_parts)
  {
    if (n_parts < 1)
      throw std::invalid_argument("bisection_owners: n_parts must be >= 1");
    std::vector<int>          owners(x.size(), 0);
    std::vector<std::int32_t> ids(x.size());
    std::iota(ids.begin(), ids.end(), 0);
    bisect(x, ids, 0, ids.size(), 0, n_parts, owners);
    return owners;
  }

  template <int dim>
  std::vector<std::int32_t> local_particles(const std::vector<Vector<dim>> &x,
                                            const std::vector<int> &owners, const int rank,
                                            const double radius, const int n_layers)
  {
    const std::size_t n = x.size();
    if (n == 0)
      return {};
    // cell list of cell size `radius`: a particle's neighbours lie in the 3^dim cells around it
    Vector<dim> lo = x[0];
    for (const auto &p : x)
      lo = lo.cwiseMin(p);
    using Key = std::array<long, dim>;
    auto key  = [&](const Vector<dim> &p) {
      Key k;
      for (int d = 0; d < dim; ++d)
        k[d] = static_cast<long>(std::floor((p[d] - lo[d]) / radius));
      return k;
    };
    std::map<Key, std::vector<std::int32_t>> cells;
    for (std::size_t i = 0; i < n; ++i)
      cells[key(x[i])].push_back(static_cast<std::int32_t>(i));
    std::vector<std::uint8_t> in(n, 0);
    std::vector<std::int32_t> frontier;
    for (std::size_t i = 0; i < n; ++i)
      if (owners[i] == rank)
        {
          in[i] = 1;
          frontier.push_back(static_cast<std::int32_t>(i));
        }
    const double r2 = radius * radius;
    for (int layer = 0; layer < n_layers; ++layer)
      {
        std::vector<std::int32_t> next;
        for (const std::int32_t i : frontier)
          {
            const Key c = key(x[i]);
            Key       o;
            const int n_cells = dim == 2 ? 9 : 27;
            for (int m = 0; m < n_cells; ++m)
              {
                int r = m;
                for (int d = 0; d < dim; ++d, r /= 3)
                  o[d] = c[d] + (r % 3) - 1;
                const auto it = cells.find(o);
                if (it == cells.end())
                  continue;
                for (const std::int32_t j : it->second)
                  if (!in[j] && (x[j] - x[i]).squaredNorm() <= r2)
                    {
                      in[j] = 1;
                      next.push_back(j);
                    }
              }
          }
        frontier.swap(next);
      }
    std::vector<std::int32_t> local;
    for (std::size_t i = 0; i < n; ++i)
      if (in[i])
        local.push_back(static_cast<std::int32_t>(i));
    return local;
  }

  Domain::Domain(MPI_Comm comm, const std::vector<int> &owners, std::vector<std::int32_t> local)
    : comm_(comm)
    , n_global_(owners.size())
    , local_(std::move(local))
  {
    check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(comm_, &n_ranks_), "MPI_Comm_size");
    owned_.assign(local_.size(), 0);
    owner_.resize(local_.size());
    for (std::size_t k = 0; k < local_.size(); ++k)
      {
        owner_[k] = owners[local_[k]];
        if (owner_[k] == rank_)
          {
            owned_[k] = 1;
            owned_indices_.push_back(static_cast<std::int32_t>(k));
          }
      }
    plan_exchange(std::vector<std::uint8_t>(local_.size(), 1));
    // every rank's owned global indices, for gather
    const int n_owned = static_cast<int>(owned_indices_.size());
    owned_counts_.assign(n_ranks_, 0);
    check(MPI_Allgather(&n_owned, 1, MPI_INT, owned_counts_.data(), 1, MPI_INT, comm_),
          "MPI_Allgather");
    std::vector<int> displ(n_ranks_, 0);
    for (int r = 1; r < n_ranks_; ++r)
      displ[r] = displ[r - 1] + owned_counts_[r - 1];
    std::vector<std::int32_t> mine;
    for (const std::int32_t k : owned_indices_)
      mine.push_back(local_[k]);
    all_owned_.resize(n_global_);
    check(MPI_Allgatherv(mine.data(), n_owned, MPI_INT32_T, all_owned_.data(),
                         owned_counts_.data(), displ.data(), MPI_INT32_T, comm_),
          "MPI_Allgatherv");
  }

  void Domain::restrict_exchange(const std::vector<std::uint8_t> &needed)
  {
    if (needed.size() != local_.size())
      throw std::invalid_argument("sph::Domain::restrict_exchange: one flag per local particle");
    plan_exchange(needed);
  }

  void Domain::plan_exchange(const std::vector<std::uint8_t> &needed)
  {
    std::vector<std::vector<std::int32_t>> wanted(n_ranks_); // global ids we receive, per owner
    for (std::size_t k = 0; k < local_.size(); ++k)
      if (owner_[k] != rank_ && needed[k])
        wanted[owner_[k]].push_back(local_[k]);
    // tell each owner which of its particles we hold as ghosts (ascending global index)
    std::vector<int> n_want(n_ranks_), n_asked(n_ranks_);
    for (int r = 0; r < n_ranks_; ++r)
      n_want[r] = static_cast<int>(wanted[r].size());
    check(MPI_Alltoall(n_want.data(), 1, MPI_INT, n_asked.data(), 1, MPI_INT, comm_),
          "MPI_Alltoall");
    std::vector<int> send_offsets(n_ranks_ + 1, 0), recv_offsets(n_ranks_ + 1, 0);
    for (int r = 0; r < n_ranks_; ++r)
      {
        send_offsets[r + 1] = send_offsets[r] + n_want[r];
        recv_offsets[r + 1] = recv_offsets[r] + n_asked[r];
      }
    std::vector<std::int32_t> flat_want, flat_asked(recv_offsets[n_ranks_]);
    for (const auto &w : wanted)
      flat_want.insert(flat_want.end(), w.begin(), w.end());
    check(MPI_Alltoallv(flat_want.data(), n_want.data(), send_offsets.data(), MPI_INT32_T,
                        flat_asked.data(), n_asked.data(), recv_offsets.data(), MPI_INT32_T,
                        comm_),
          "MPI_Alltoallv");
    auto local_index = [&](const std::int32_t g) {
      const auto it = std::lower_bound(local_.begin(), local_.end(), g);
      if (it == local_.end() || *it != g)
        throw std::logic_error("sph::Domain: a ghost asked for a particle this rank lacks");
      return static_cast<std::int32_t>(it - local_.begin());
    };
    peers_.clear();
    send_rows_.clear();
    recv_rows_.clear();
    for (int r = 0; r < n_ranks_; ++r)
      {
        if (n_want[r] == 0 && n_asked[r] == 0)
          continue;
        peers_.push_back(r);
        std::vector<std::int32_t> s, g;
        for (int k = recv_offsets[r]; k < recv_offsets[r + 1]; ++k)
          s.push_back(local_index(flat_asked[k]));
        for (const std::int32_t id : wanted[r])
          g.push_back(local_index(id));
        send_rows_.push_back(std::move(s));
        recv_rows_.push_back(std::move(g));
      }
  }

  void Domain::exchange(const std::vector<std::pair<double *, int>> &fields) const
  {
    int width = 0;
    for (const auto &f : fields)
      width += f.second;
    const std::size_t                n_peers = peers_.size();
    std::vector<std::vector<double>> out(n_peers), in(n_peers);
    std::vector<MPI_Request>         requests(2 * n_peers);
    for (std::size_t p = 0; p < n_peers; ++p)
      {
        in[p].resize(recv_rows_[p].size() * width);
        check(MPI_Irecv(in[p].data(), static_cast<int>(in[p].size()), MPI_DOUBLE, peers_[p], 7,
                        comm_, &requests[p]),
              "MPI_Irecv");
      }
    for (std::size_t p = 0; p < n_peers; ++p)
      {
        out[p].resize(send_rows_[p].size() * width);
        double *o = out[p].data();
        for (const std::int32_t k : send_rows_[p])
          for (const auto &[field, w] : fields)
            for (int c = 0; c < w; ++c)
              *o++ = field[static_cast<std::size_t>(k) * w + c];
        check(MPI_Isend(out[p].data(), static_cast<int>(out[p].size()), MPI_DOUBLE, peers_[p], 7,
                        comm_, &requests[n_peers + p]),
              "MPI_Isend");
      }
    {
      const Stopwatch watch(wait_seconds_);
      check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
            "MPI_Waitall");
    }
    for (std::size_t p = 0; p < n_peers; ++p)
      {
        const double *i = in[p].data();
        for (const std::int32_t k : recv_rows_[p])
          for (const auto &[field, w] : fields)
            for (int c = 0; c < w; ++c)
              field[static_cast<std::size_t>(k) * w + c] = *i++;
      }
  }

  std::size_t Domain::n_sent(const int width) const
  {
    std::size_t n = 0;
    for (const auto &rows : send_rows_)
      n += rows.size() * width;
    return n;
  }

  std::vector<double> Domain::gather_owned(const double *owned_rows, const int width) const
  {
    std::vector<int> counts(n_ranks_), displ(n_ranks_, 0);
    for (int r = 0; r < n_ranks_; ++r)
      counts[r] = owned_counts_[r] * width;
    for (int r = 1; r < n_ranks_; ++r)
      displ[r] = displ[r - 1] + counts[r - 1];
    std::vector<double> all(n_global_ * width);
    const Stopwatch     watch(wait_seconds_);
    check(MPI_Allgatherv(owned_rows, counts[rank_], MPI_DOUBLE, all.data(), counts.data(),
                         displ.data(), MPI_DOUBLE, comm_),
          "MPI_Allgatherv");
    std::vector<double> global(n_global_ * width);
    for (std::size_t k = 0; k < n_global_; ++k)
      std::copy(all.begin() + k * width, all.begin() + (k + 1) * width,
                global.begin() + static_cast<std::size_t>(all_owned_[k]) * width);
    return global;
  }

  std::vector<double> Domain::gather(const double *field, const int width) const
  {
    std::vector<double> mine(owned_indices_.size() * width);
    for (std::size_t m = 0; m < owned_indices_.size(); ++m)
      std::copy(field + static_cast<std::size_t>(owned_indices_[m]) * width,
                field + (static_cast<std::size_t>(owned_indices_[m]) + 1) * width,
                mine.begin() + m * width);
    return gather_owned(mine.data(), width);
  }

  std::vector<double> Domain::scatter(const std::vector<double> &global, const int width) const
  {
    std::vector<double> rows(local_.size() * width);
    for (std::size_t k = 0; k < local_.size(); ++k)
      std::copy(global.begin() + static_cast<std::size_t>(local_[k]) * width,
                global.begin() + (static_cast<std::size_t>(local_[k]) + 1) * width,
                rows.begin() + k * width);
    return rows;
  }

  std::vector<double> Domain::all_gather(const std::vector<double> &values) const
  {
    const int           n = static_cast<int>(values.size());
    std::vector<double> all(static_cast<std::size_t>(n) * n_ranks_);
    const Stopwatch     watch(wait_seconds_);
    check(MPI_Allgather(values.data(), n, MPI_DOUBLE, all.data(), n, MPI_DOUBLE, comm_),
          "MPI_Allgather");
    return all;
  }

  std::vector<double> Domain::sum(const std::vector<double> &values) const
  {
    const int                 n   = static_cast<int>(values.size());
    const std::vector<double> all = all_gather(values);
    std::vector<double> s(values.size(), 0.0);
    for (int r = 0; r < n_ranks_; ++r)
      for (int k = 0; k < n; ++k)
        s[k] += all[static_cast<std::size_t>(r) * n + k];
    return s;
  }

  double Domain::min(const double value) const
  {
    double          m = value;
    const Stopwatch watch(wait_seconds_);
    check(MPI_Allreduce(&value, &m, 1, MPI_DOUBLE, MPI_MIN, comm_), "MPI_Allreduce");
    return m;
  }

  double Domain::max(const double value) const
  {
    double          m = value;
    const Stopwatch watch(wait_seconds_);
    check(MPI_Allreduce(&value, &m, 1, MPI_DOUBLE, MPI_MAX, comm_), "MPI_Allreduce");
    return m;
  }

  void Domain::sum_in_place(double *values, const int n) const
  {
    const Stopwatch watch(wait_seconds_);
    check(MPI_Allreduce(MPI_IN_PLACE, values, n, MPI_DOUBLE, MPI_SUM, comm_), "MPI_Allreduce");
  }

  template std::vector<int> bisection_owners<2>(const std::vector<Vector<2>> &, int);
  template std::vector<int> bisection_owners<3>(const std::vector<Vector<3>> &, int);
  template std::vector<std::int32_t> local_particles<2>(const std::vector<Vector<2>> &,
                                                        const std::vector<int> &, int, double,
                                                        int);
  template std::vector<std::int32_t> local_particles<3>(const std::vector<Vector<3>> &,
                                                        const std::vector<int> &, int, double,
                                                        int);
} // namespace sph

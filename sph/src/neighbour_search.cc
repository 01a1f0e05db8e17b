#include <sph/neighbour_search.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace sph
{
  // pair indices ascend within each particle
  void build_incidence(const std::size_t n, PairList &pairs)
  {
    pairs.offsets.assign(n + 1, 0);
    for (std::size_t p = 0; p < pairs.n_pairs(); ++p)
      {
        ++pairs.offsets[pairs.first[p] + 1];
        ++pairs.offsets[pairs.second[p] + 1];
      }
    for (std::size_t i = 0; i < n; ++i)
      pairs.offsets[i + 1] += pairs.offsets[i];
    pairs.incidence.resize(pairs.offsets[n]);
    std::vector<std::int32_t> fill(pairs.offsets.begin(), pairs.offsets.end() - 1);
    for (std::size_t p = 0; p < pairs.n_pairs(); ++p)
      {
        pairs.incidence[fill[pairs.first[p]]++]  = static_cast<std::int32_t>(p);
        pairs.incidence[fill[pairs.second[p]]++] = static_cast<std::int32_t>(p);
      }
  }

  template <int dim>
  void find_pairs(const std::vector<Vector<dim>> &x, const double radius, PairList &pairs)
  {
    const std::size_t n = x.size();
    pairs.first.clear();
    pairs.second.clear();
    if (n == 0)
      {
        build_incidence(0, pairs);
        return;
      }
    if (!(radius > 0))
      throw std::invalid_argument("sph::find_pairs: the cut-off radius must be positive");
    Vector<dim> lo = x[0], hi = x[0];
    for (const auto &p : x)
      {
        if (!p.allFinite())
          throw std::runtime_error("sph::find_pairs: non-finite particle position (the run "
                                   "went unstable; reduce the time step)");
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    // cell size >= radius; coarser if the box would need far more cells than particles
    double cell = radius;
    auto   count_cells = [&](const double c) {
      double t = 1;
      for (int d = 0; d < dim; ++d)
        t *= std::floor((hi[d] - lo[d]) / c) + 1;
      return t;
    };
    while (count_cells(cell) > 8.0 * n + 1000)
      cell *= 1.5;
    std::array<long, dim> nc;
    for (int d = 0; d < dim; ++d)
      nc[d] = static_cast<long>(std::floor((hi[d] - lo[d]) / cell)) + 1;
    long n_total = 1;
    for (int d = 0; d < dim; ++d)
      n_total *= nc[d];

    std::vector<std::array<long, dim>> coord(n);
    std::vector<long>                  cell_of(n);
    std::vector<std::int32_t>          start(n_total + 1, 0), sorted(n);
    for (std::size_t i = 0; i < n; ++i)
      {
        long c = 0;
        for (int d = dim - 1; d >= 0; --d)
          {
            coord[i][d] = std::min(nc[d] - 1, static_cast<long>((x[i][d] - lo[d]) / cell));
            c           = c * nc[d] + coord[i][d];
          }
        cell_of[i] = c;
        ++start[c + 1];
      }
    for (long c = 0; c < n_total; ++c)
      start[c + 1] += start[c];
    {
      std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
      for (std::size_t i = 0; i < n; ++i)
        sorted[fill[cell_of[i]]++] = static_cast<std::int32_t>(i);
    }

    const double r2 = radius * radius;
    // per particle: its partners j > i, sorted; then concatenate (deterministic)
    std::vector<std::int32_t> n_partners(n + 1, 0);
    std::vector<std::vector<std::int32_t>> partners(n);
    const int n_stencil = dim == 2 ? 9 : 27;
#pragma omp parallel for schedule(static)
    for (long i = 0; i < static_cast<long>(n); ++i)
      {
        auto &list = partners[i];
        list.clear();
        for (int s = 0; s < n_stencil; ++s)
          {
            std::array<long, dim> c;
            int                   r = s;
            bool                  inside = true;
            for (int d = 0; d < dim; ++d)
              {
                c[d] = coord[i][d] + (r % 3) - 1;
                r /= 3;
                inside = inside && c[d] >= 0 && c[d] < nc[d];
              }
            if (!inside)
              continue;
            long cc = 0;
            for (int d = dim - 1; d >= 0; --d)
              cc = cc * nc[d] + c[d];
            for (std::int32_t k = start[cc]; k < start[cc + 1]; ++k)
              {
                const std::int32_t j = sorted[k];
                if (j > i && (x[i] - x[j]).squaredNorm() < r2)
                  list.push_back(j);
              }
          }
        std::sort(list.begin(), list.end());
        n_partners[i + 1] = static_cast<std::int32_t>(list.size());
      }
    for (std::size_t i = 0; i < n; ++i)
      n_partners[i + 1] += n_partners[i];
    pairs.first.resize(n_partners[n]);
    pairs.second.resize(n_partners[n]);
#pragma omp parallel for schedule(static)
    for (long i = 0; i < static_cast<long>(n); ++i)
      {
        std::int32_t p = n_partners[i];
        for (const std::int32_t j : partners[i])
          {
            pairs.first[p]  = static_cast<std::int32_t>(i);
            pairs.second[p] = j;
            ++p;
          }
      }
    build_incidence(n, pairs);
  }

  template <int dim>
  void find_pairs_brute_force(const std::vector<Vector<dim>> &x, const double radius,
                              PairList &pairs)
  {
    pairs.first.clear();
    pairs.second.clear();
    for (std::size_t i = 0; i < x.size(); ++i)
      for (std::size_t j = i + 1; j < x.size(); ++j)
        if ((x[i] - x[j]).squaredNorm() < radius * radius)
          {
            pairs.first.push_back(static_cast<std::int32_t>(i));
            pairs.second.push_back(static_cast<std::int32_t>(j));
          }
    build_incidence(x.size(), pairs);
  }

  template void find_pairs<2>(const std::vector<Vector<2>> &, double, PairList &);
  template void find_pairs<3>(const std::vector<Vector<3>> &, double, PairList &);
  template void find_pairs_brute_force<2>(const std::vector<Vector<2>> &, double, PairList &);
  template void find_pairs_brute_force<3>(const std::vector<Vector<3>> &, double, PairList &);
} // namespace sph

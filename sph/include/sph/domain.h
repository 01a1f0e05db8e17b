#pragma once
/// @file
/// Distributed SPH bodies: the split of the particles into spatial subdomains (recursive
/// coordinate bisection of the reference positions), each rank's local particle set (its own
/// particles plus the ghost layers their forces need) and the halo exchange that refreshes the
/// ghosts from their owners (MPI, non-blocking, one packed message per neighbouring rank).
///
/// Particles are named by their global index (their place in the serial body). A rank's local
/// body holds its local set in ascending global index, so every per-particle sum over the
/// neighbours runs in the serial order (pairs are sorted by index; see sph::Body).

#include <sph/types.h>

#include <mpi.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace sph
{
  /// The rank of each particle among `n_parts` subdomains: recursive coordinate bisection of
  /// `x` [m] (each cut across the longest side of the set's bounding box, at the particle whose
  /// share of the parts it ends; ties by index). Deterministic: the same input gives the same
  /// split on every rank.
  template <int dim>
  std::vector<int> bisection_owners(const std::vector<Vector<dim>> &x, int n_parts);

  /// The global indices, ascending, of the particles within `n_layers` neighbour hops of the
  /// particles owned by `rank` (a hop: distance at most `radius` [m]), the owned ones included.
  template <int dim>
  std::vector<std::int32_t> local_particles(const std::vector<Vector<dim>> &x,
                                            const std::vector<int> &owners, int rank,
                                            double radius, int n_layers);

  /// One rank's share of a distributed body: which local particles it owns, their global
  /// indices, and the ghost exchange with the other ranks.
  class Domain
  {
  public:
    /// The split of `owners.size()` particles by `owners` (bisection_owners) with this rank's
    /// local set `local` (ascending global indices, local_particles). Collective over `comm`
    /// (the ghost lists are exchanged once).
    Domain(MPI_Comm comm, const std::vector<int> &owners, std::vector<std::int32_t> local);

    /// The communicator.
    MPI_Comm comm() const { return comm_; }
    /// This rank and the number of ranks.
    int rank() const { return rank_; }
    int n_ranks() const { return n_ranks_; }
    /// Number of particles of the whole body.
    std::size_t n_global() const { return n_global_; }
    /// Global index of each local particle (ascending).
    const std::vector<std::int32_t> &global_ids() const { return local_; }
    /// 1 for each local particle this rank owns, 0 for a ghost.
    const std::vector<std::uint8_t> &owned() const { return owned_; }
    /// The local indices of the owned particles, ascending.
    const std::vector<std::int32_t> &owned_indices() const { return owned_indices_; }
    /// Number of ghosts held (restrict_exchange does not change it).
    std::size_t n_ghosts() const { return local_.size() - owned_indices_.size(); }

    /// From now on `exchange` refreshes only the ghosts flagged in `needed` (one flag per local
    /// particle; owned ones are ignored): those whose fields a step reads. Collective.
    /// std::invalid_argument for a wrong size.
    void restrict_exchange(const std::vector<std::uint8_t> &needed);

    /// Refreshes the ghosts' entries of `width` doubles each in `field` (one row per local
    /// particle) from their owners: one packed message per neighbouring rank, non-blocking.
    /// Collective.
    void exchange(double *field, int width) const { exchange({{field, width}}); }
    /// The same for several fields at once (each a pointer and a width), in one message per
    /// neighbouring rank.
    void exchange(const std::vector<std::pair<double *, int>> &fields) const;
    /// Doubles this rank sends per exchange of `width` doubles per ghost.
    std::size_t n_sent(int width) const;

    /// The rows of the owned particles of `field` (`width` doubles per local particle) gathered
    /// on every rank into one array in global order (`width` doubles per particle). Collective.
    std::vector<double> gather(const double *field, int width) const;
    /// The same for an array with one row per owned particle (owned_indices order).
    std::vector<double> gather_owned(const double *owned_rows, int width) const;
    /// The rows of the local particles picked out of `global` (`width` doubles per particle, in
    /// global order).
    std::vector<double> scatter(const std::vector<double> &global, int width) const;

    /// Sum over the ranks in rank order of each entry of `values` (the same size on every rank):
    /// one collective, the same bits on every rank and in every run with this rank count.
    std::vector<double> sum(const std::vector<double> &values) const;
    /// Every rank's `values` (the same size on every rank), concatenated in rank order. One
    /// collective.
    std::vector<double> all_gather(const std::vector<double> &values) const;
    /// Sum of one value (see sum).
    double sum(double value) const { return sum(std::vector<double>{value})[0]; }
    /// Minimum and maximum over the ranks.
    double min(double value) const;
    double max(double value) const;
    /// `values` (`n` entries, the same count on every rank) replaced by their sum over the ranks:
    /// one MPI_Allreduce (the order of the sum is MPI's: exact for two ranks).
    void sum_in_place(double *values, int n) const;

    /// Wall-clock seconds this rank has spent waiting for the exchanges (after posting them) and
    /// inside the collectives above: latency, transfer and the wait for slower ranks.
    double wait_seconds() const { return wait_seconds_; }

  private:
    // the send and receive lists of the ghosts flagged in `needed` (one flag per local particle)
    void plan_exchange(const std::vector<std::uint8_t> &needed);

    MPI_Comm                  comm_;
    int                       rank_ = 0, n_ranks_ = 1;
    std::size_t               n_global_ = 0;
    std::vector<std::int32_t> local_;
    std::vector<std::uint8_t> owned_;
    std::vector<std::int32_t> owned_indices_;
    std::vector<int>          owner_; // per local particle: its owner's rank
    // per neighbouring rank: the local indices of the rows sent to it and received from it
    std::vector<int>                       peers_;
    std::vector<std::vector<std::int32_t>> send_rows_, recv_rows_;
    // gather: every rank's owned global indices (concatenated in rank order) and counts
    std::vector<std::int32_t> all_owned_;
    std::vector<int>          owned_counts_;
    mutable double            wait_seconds_ = 0;
  };
} // namespace sph

#pragma once
// A plane-parallel problem (solver/plane_parallel.hpp) spread over the processes of an MPI
// communicator: MpiSplit, a PassSplit. Needs MPI (CMake: the secchi::mpi target, where
// find_package(MPI COMPONENTS CXX) finds it); nothing else in secchi does.
//
// Contract: with R processes, B batches and S shards (PlaneParallelConfig::shards; S a multiple
// of R, B a multiple of S), rank r traces the whole batches [B r / R, B (r+1) / R) (photons
// [N r / R, N (r+1) / R): disjoint photon ranges, so the batches stay independent) and builds
// the shards [S r / R, S (r+1) / R) from the records it traced itself: records never travel.
// What travels to rank 0:
//  - first pass: every traced block's tallies (4 irradiances per detector depth, Ed on the
//    bottom and per bottom bin, Ed(0+) direct and diffuse, Eu(0+), the ledger's accounts), merged there in block
//    order exactly as one process merges them (tracer.hpp's merge_part);
//  - second pass: per depth, the per-batch Lu sums of the rank's batches (RadianceSum) and the
//    photons touched; batch k's sum is the one shard holding it, as in one process.
// So a seed gives the same bits on rank 0 for any R dividing S, any thread count per rank, and
// the single-process solve with the same S (examples/slab --shards S). The other ranks' results
// hold their own share only. A run over several processes needs map photons = photons and
// photons divisible by the batches (each photon's map batch is then its first-pass batch: its
// records are on the rank that holds their shard). Scaling model: docs/distributed.md.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <mpi.h>
#include <cstdint>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

/// A PassSplit over an MPI communicator (MPI initialised by the caller). Every rank must call
/// the solver with the same configuration.
class MpiSplit {
public:
    explicit MpiSplit(MPI_Comm comm = MPI_COMM_WORLD) : comm_(comm) {
        int rank = 0, size = 1;
        MPI_Comm_rank(comm_, &rank);
        MPI_Comm_size(comm_, &size);
        rank_ = static_cast<unsigned>(rank);
        ranks_ = static_cast<unsigned>(size);
    }

    [[nodiscard]] unsigned rank() const { return rank_; }
    [[nodiscard]] unsigned ranks() const { return ranks_; }

    /// Every rank's traced blocks' tallies into rank 0's part, in block order (the ranks hold
    /// contiguous block ranges in rank order).
    template <class Record>
    void gather_tallies(FirstPassPart<Record>& part) const {
        if (ranks_ == 1) return;
        std::vector<double> mine;
        for (std::size_t i = part.traced.first; i < part.traced.last; ++i) pack(part.results[i], mine);
        const std::vector<double> all = gather(mine);
        if (rank_ != 0) return;
        const std::size_t per_block = block_doubles(part.results.front());
        require(all.size() == per_block * part.results.size(), "gathered block tallies", all.size(),
                "must be " + std::to_string(per_block) + " per block of " + std::to_string(part.results.size()) +
                    " (do the ranks trace every block exactly once?)");
        const double* p = all.data();
        for (auto& r : part.results) p = unpack(p, r);
    }

    /// n summed over the ranks, on rank 0 (elsewhere n).
    [[nodiscard]] std::uint64_t total(std::uint64_t n) const {
        unsigned long long sum = 0, mine = n;
        MPI_Reduce(&mine, &sum, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, comm_);
        return rank_ == 0 ? sum : n;
    }

    /// Each depth's per-batch sums of batches [first, last) (this rank's) and its photons
    /// touched into rank 0's sums.
    void gather_lu(std::vector<RadianceSum>& sums, unsigned first, unsigned last) const {
        if (ranks_ == 1) return;
        std::vector<double> mine;
        for (const RadianceSum& s : sums) {
            for (unsigned k = first; k < last; ++k) mine.push_back(s.per_batch()[k]);
        }
        std::vector<unsigned long long> touched(sums.size()), total(sums.size());
        for (std::size_t d = 0; d < sums.size(); ++d) touched[d] = sums[d].photons_touched();
        MPI_Reduce(touched.data(), total.data(), static_cast<int>(sums.size()), MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, comm_);
        // Every rank holds the same number of batches (B / R); rank q's are [B q / R, B (q+1) / R).
        const std::vector<double> all = gather(mine);
        if (rank_ != 0) return;
        const std::size_t per_rank = last - first, batches = per_rank * ranks_;
        require(all.size() == per_rank * ranks_ * sums.size(), "gathered Lu sums", all.size(),
                "must be one per batch and depth");
        for (unsigned q = 1; q < ranks_; ++q)
            for (std::size_t d = 0; d < sums.size(); ++d)
                for (std::size_t j = 0; j < per_rank; ++j)
                    sums[d].per_batch()[batches * q / ranks_ + j] = all[(q * sums.size() + d) * per_rank + j];
        for (std::size_t d = 0; d < sums.size(); ++d) sums[d].count_photons(total[d] - touched[d]);
    }

private:
    template <class Record>
    static std::size_t block_doubles(const detail::BlockResult<Record>& r) {
        return 4 * r.tally.size() + 4 + r.bottom_bins.size() + EnergyLedger::accounts;
    }
    template <class Record>
    static void pack(const detail::BlockResult<Record>& r, std::vector<double>& out) {
        for (const auto& t : r.tally) out.insert(out.end(), t.begin(), t.end());
        out.insert(out.end(), {r.bottom_ed, r.ed_direct, r.ed_diffuse, r.eu_air});
        out.insert(out.end(), r.bottom_bins.begin(), r.bottom_bins.end());
        const auto ledger = r.ledger.values();
        out.insert(out.end(), ledger.begin(), ledger.end());
    }
    template <class Record>
    static const double* unpack(const double* p, detail::BlockResult<Record>& r) {
        for (auto& t : r.tally)
            for (double& v : t) v = *p++;
        for (double* v : {&r.bottom_ed, &r.ed_direct, &r.ed_diffuse, &r.eu_air}) *v = *p++;
        for (double& v : r.bottom_bins) v = *p++;
        for (double* v : r.ledger.entries()) *v = *p++;
        return p;
    }

    /// Every rank's doubles on rank 0, concatenated in rank order (empty elsewhere).
    std::vector<double> gather(const std::vector<double>& mine) const {
        require(mine.size() <= static_cast<std::size_t>(INT32_MAX), "doubles sent by one rank", mine.size(),
                "exceed what one MPI message counts (2^31 - 1)");
        const int n = static_cast<int>(mine.size());
        std::vector<int> counts(rank_ == 0 ? ranks_ : 0), offsets(counts.size());
        MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_);
        std::vector<double> all;
        if (rank_ == 0) {
            std::size_t total = 0;
            for (std::size_t q = 0; q < counts.size(); ++q) {
                require(total <= static_cast<std::size_t>(INT32_MAX), "doubles gathered", total,
                        "exceed what one MPI message counts (2^31 - 1)");
                offsets[q] = static_cast<int>(total);
                total += static_cast<std::size_t>(counts[q]);
            }
            all.resize(total);
        }
        MPI_Gatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, 0, comm_);
        return all;
    }

    MPI_Comm comm_;
    unsigned rank_ = 0, ranks_ = 1;
};

static_assert(PassSplit<MpiSplit>);

}  // namespace secchi

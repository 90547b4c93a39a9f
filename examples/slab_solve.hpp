#pragma once
// slab's run, compiled once (examples/slab_solve.cpp, an object library) for both programs that
// use it: slab on one process and slab_mpi spread over MPI ranks. Both passes are instantiated
// for every phase model of the command line (AnyPhase); the processes' split is an AnyPassSplit,
// so the instantiation does not depend on it.
#include "secchi/optics/phase/any_phase.hpp"
#include "secchi/solver/plane_parallel.hpp"

namespace secchi::examples::slab {

/// solve_plane_parallel with the phase function the command line chose, spread by `split`
/// (complete on rank 0; see solve_plane_parallel_in).
PlaneParallelResult solve(const AnyPhase& phase, const PlaneParallelConfig& cfg, const AnyPassSplit& split = {});

}  // namespace secchi::examples::slab

// slab's run for every phase model and any split (examples/slab_solve.hpp).
#include "slab_solve.hpp"
#include <variant>

namespace secchi::examples::slab {

PlaneParallelResult solve(const AnyPhase& phase, const PlaneParallelConfig& cfg, const AnyPassSplit& split) {
    return std::visit([&](const auto& p) { return solve_plane_parallel(p, cfg, split); }, phase);
}

}  // namespace secchi::examples::slab

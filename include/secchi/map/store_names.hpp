#pragma once
// The registry of photon-store names, the one table that the programs' --store option
// (parse_store), their usage texts (store_usage) and their error messages read:
//   kdtree | voi | voi-grid | nanoflann | brute-force   (no aliases).
// Which store and query each kind runs: solve_plane_parallel (solver/plane_parallel.hpp).
#include "secchi/core/config.hpp"
#include <string>
#include <vector>

#include "secchi/core/names.hpp"

namespace secchi::SECCHI_ISA {

enum class StoreKind { kdtree, voi, voi_grid, nanoflann, brute_force };

/// Every store, in the order the usage texts list them.
inline const std::vector<NamedValue<StoreKind>>& store_names() {
    static const std::vector<NamedValue<StoreKind>> names{
        {{"kdtree", {}, "Jensen's left-balanced k-d tree (map/kdtree.hpp), spheres at --steps points along each ray"},
         StoreKind::kdtree},
        {{"voi", {}, "the VOI octree (map/voi_octree.hpp), one cylinder query per ray"}, StoreKind::voi},
        {{"voi-grid", {}, "the VOI grid (map/voi_grid.hpp): the cylinder query over columns r/2 wide"},
         StoreKind::voi_grid},
        {{"nanoflann", {}, "the nanoflann k-d tree adaptor (map/nanoflann_store.hpp), spheres as kdtree"},
         StoreKind::nanoflann},
        {{"brute-force", {}, "every photon tested (map/brute_force.hpp, the oracle), the cylinder query"},
         StoreKind::brute_force},
    };
    return names;
}

/// The store's canonical name.
inline std::string to_string(StoreKind k) { return name_of(store_names(), k); }

/// "kdtree|voi|...": the --store choices of a usage text.
inline std::string store_usage() { return usage_names(store_names()); }

/// The store a name gives; input_error naming the value and the valid names.
inline StoreKind parse_store(const std::string& s) { return parse_named(store_names(), "store", s); }

}  // namespace secchi

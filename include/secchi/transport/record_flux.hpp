#pragma once
// What one stored record of the photon map stands for. Every stored photon carries an equal
// share of the incident flux (manual 3.3.2.4): Phi = Ed(0+) A / N_map (A the section's area,
// N_map the photons whose events are stored), except where the first pass split photons by
// depth importance, which stores I(z) times more records at depth z, each carrying Phi / I(z),
// and where it stored photons by their direction of travel (upward importance: D(mu) times
// more records of photons travelling at upward cosine mu, each carrying Phi / D(mu))
// (transport/importance.hpp). The first pass writes this into its result, with the depth down
// to which it stored events; the estimators take it from there, so that the normalisation is
// the map's own and no optics policy can apply or forget it.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/transport/importance.hpp"
#include <cmath>

namespace secchi::SECCHI_ISA {

struct RecordFlux {
    double per_record = 0.0;             ///< Phi (W nm^-1): the flux of a record at importance 1
    ImportanceLevels importance;         ///< I(z) of the first pass (off: I = 1 everywhere)
    double stored_to_depth = INFINITY;   ///< m: events deeper than this were not stored
    UpwardImportance upward;             ///< D(mu) of the first pass (off: D = 1 everywhere)

    /// A map of equal-flux records without depth importance, complete at every depth (a map
    /// made by hand, e.g. in a test).
    static RecordFlux uniform(double phi) {
        require(std::isfinite(phi) && phi >= 0.0, "flux per record", phi, "must be finite and >= 0");
        return {phi, {}, INFINITY, {}};
    }
    /// Whether every record carries the same flux.
    [[nodiscard]] bool is_uniform() const { return !importance.enabled() && !upward.enabled(); }
    /// The flux of a record stored at depth z travelling with z component dz: Phi / (I(z) D(-dz)).
    [[nodiscard]] double at(double z, double dz) const {
        return is_uniform() ? per_record : per_record / record_importance(importance, upward, z, dz);
    }
};

}  // namespace secchi

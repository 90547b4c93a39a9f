#pragma once
// Settings of the first pass (manual 3.3): photon budget, seed, threads, batches, detector
// depths, and how absorption and long histories are handled.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/names.hpp"
#include "secchi/transport/importance.hpp"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

/// How absorption is applied at an interaction (both unbiased):
///  - analog: the photon is absorbed with probability 1 - w0 and otherwise scattered (manual
///    3.3.5); every stored photon carries the same flux.
///  - implicit_capture: the photon always scatters and its weight is multiplied by w0
///    (survival biasing, "absorption weighting"); the absorbed part goes to the ledger. Stored
///    photons keep equal flux: a scattering event is stored with probability equal to the
///    photon's weight. Far more photons reach deep detectors (essential at w0 = 0.2).
///  - continuous: free paths are drawn from the scattering coefficient b alone and the
///    weight decays continuously as exp(-a s) along every flight (detectors see the weight
///    where they are crossed); every interaction is a scattering, stored with probability
///    equal to the weight. Photons follow the paths of a non-absorbing medium, so deep
///    detectors in strongly absorbing, forward-scattering water (w0 = 0.2) get far more,
///    far less skewed contributions than with a factor w0 per collision.
enum class AbsorptionMode { analog, implicit_capture, continuous };

/// The --absorption names (core/names.hpp), in the order the usage texts list them.
inline const std::vector<NamedValue<AbsorptionMode>>& absorption_names() {
    static const std::vector<NamedValue<AbsorptionMode>> names{
        {{"continuous", {}, "free paths from b, weight exp(-a s) along each flight"}, AbsorptionMode::continuous},
        {{"implicit", {"implicit-capture"}, "weight x w0 at each interaction"}, AbsorptionMode::implicit_capture},
        {{"analog", {}, "absorbed with probability 1 - w0 at each interaction"}, AbsorptionMode::analog},
    };
    return names;
}

inline AbsorptionMode parse_absorption(const std::string& name) {
    return parse_named(absorption_names(), "absorption", name);
}

struct TransportSettings {
    std::uint64_t photons = 1'000'000;  ///< photons shot (their flux normalises everything: manual 3.3.3)
    std::uint64_t map_photons = 0;      ///< the first photons (by index) whose scattering events are stored; 0 = none
    double map_depth = INFINITY;        ///< m: events deeper than this are not stored (photons are still traced)
    std::uint64_t seed = 1;
    /// The band index every stored record carries (manual 3.3.1.2): a spectral run traces each
    /// band with its own IOPs and its own index (solver/spectral.hpp).
    std::uint8_t band = 0;
    unsigned threads = 1;
    unsigned batches = 32;              ///< independent batches for standard errors (>= 16 recommended)
    std::vector<double> depths;         ///< irradiance detector depths (m)
    /// The deepest of `depths` (m; 0 without any): where depth importance peaks by default.
    [[nodiscard]] double deepest_detector() const {
        return depths.empty() ? 0.0 : *std::max_element(depths.begin(), depths.end());
    }
    /// Ed on the bottom in bottom_bins x bottom_bins bins over the section (bottom_grid.hpp); 0: none.
    unsigned bottom_bins = 0;
    /// Keep the map photons' arrivals on objects and on an opaque bottom: the surface photon
    /// map (TransportResult::surface_photons; map/surface_record.hpp).
    bool surface_map = false;
    /// Scalar irradiances score a crossing 1/|mu|, or 2/mu_c below this cosine (irradiance_planes.hpp).
    double grazing_cosine = 0.05;
    AbsorptionMode absorption = AbsorptionMode::continuous;
    /// Cumulative-probability limit (manual 3.3.8, 7.3.2), applied without bias as Russian
    /// roulette: a photon whose weight (its cumulative survival probability) falls below
    /// roulette_weight survives with probability roulette_survival and is re-weighted by its
    /// inverse. 0 disables it (then implicit capture follows photons until they leave).
    double roulette_weight = 1e-2;
    double roulette_survival = 0.1;
    /// Scattering-order limit (manual 3.3.8): a photon that has scattered max_order times
    /// stops at its next interaction, unstored (a biased truncation; 0 = none). With 1 the
    /// map holds exactly the single-scattering source.
    unsigned max_order = 0;
    std::uint64_t block_size = 4096;    ///< photons per work unit (does not change results)
    DepthImportance importance;         ///< depth splitting (importance.hpp); off by default
    /// The share of scattering events whose angle is drawn from the phase function's backward
    /// part, their weights corrected (importance.hpp, BackscatterBias); 0 = off (the default).
    double backscatter_bias = 0.0;
    /// The share of scattering events whose direction is drawn from a lobe about straight up,
    /// and the stored events' flux set by their direction (importance.hpp, UpwardImportance);
    /// 0 = off (the default). upward_lobe: the lobe's Henyey-Greenstein asymmetry.
    double upward_importance = 0.0;
    double upward_lobe = 0.9;

    void validate() const {
        require(photons > 0, "photons", photons, "must be > 0");
        require(map_photons <= photons, "map photons", map_photons, "must not exceed the photons shot");
        require(map_depth >= 0.0, "map depth (m)", map_depth, "must be >= 0");
        require(threads >= 1, "threads", threads, "must be >= 1");
        require(batches >= 2 && batches <= 256, "batches", batches, "must be in [2, 256]");
        require(photons >= batches, "photons", photons, "must be at least the number of batches");
        require(grazing_cosine > 0.0 && grazing_cosine < 1.0, "grazing cosine", grazing_cosine, "must be in (0, 1)");
        require(roulette_weight >= 0.0 && roulette_weight < 1.0, "roulette weight", roulette_weight, "must be in [0, 1)");
        require(roulette_survival > 0.0 && roulette_survival <= 1.0, "roulette survival", roulette_survival,
                "must be in (0, 1]");
        require(block_size > 0, "block size", block_size, "must be > 0");
        require(bottom_bins <= 4096, "bottom bins", bottom_bins, "must be <= 4096 per side");
        for (double z : depths) require(z >= 0.0, "detector depth", z, "must be >= 0");
        importance.validate();
        require(std::isfinite(backscatter_bias) && backscatter_bias >= 0.0 && backscatter_bias < 1.0, "backscatter bias",
                backscatter_bias, "must be in [0, 1) (0 = off)");
        require(backscatter_bias == 0.0 || absorption != AbsorptionMode::analog, "backscatter bias", backscatter_bias,
                "needs weighted photons (absorption implicit or continuous, not analog): analog photons store every "
                "event whatever its weight");
        UpwardImportance::checked_share(upward_importance);
        UpwardImportance::checked_lobe(upward_lobe);
        require(upward_importance == 0.0 || backscatter_bias == 0.0, "upward importance", upward_importance,
                "cannot be combined with a backscatter bias (both bias the scattering direction)");
    }
};

}  // namespace secchi

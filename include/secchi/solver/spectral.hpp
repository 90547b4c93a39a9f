#pragma once
// A spectral run: several bands in one photon map (manual 3.3.1.2 and 3.3.2.5). The band list
// drives the IOPs: one Medium per band (the water at each band's centre wavelength, e.g. a
// material file's IOP model sampled there: optics/iop/linear_model.hpp, stratify()). Each
// band's photons are traced through its own medium (the first pass of plane_parallel.hpp, with
// that band's seed and index), and every stored record carries its band index; the map holds
// them all, and the second pass estimates per band (estimate/radiance.hpp: radiance(ray, band),
// with each band's ray optics).
//
// Photons per band: the manual's rule, "the number of photons of a particular wavelength index
// should be proportional to the aggregate weight of that index" (3.3.1.2), so that every record
// carries the same flux. The light source here has the same spectrum value in every band (the
// canonical E_perp = 1 per nm, or the sky's plane irradiance), so each band traces
// cfg.transport.photons and stores cfg.transport.map_photons: every record carries the same
// flux, which is checked. Radiances and irradiances are per nm of that flat source spectrum;
// reflectances (Rrs = Lw / Ed(0+), R = Eu / Ed) do not depend on it.
//
// Band k's photons use the seed cfg.transport.seed + k * 0x9E3779B97F4A7C15 (mod 2^64; band 0
// keeps the run's seed, so that a one-band spectral run is the plain run), so that the bands'
// random streams are independent. The surface's refractive index is band 0's (a material's
// n(lambda) changes by about 0.005 over 400-700 nm, 0.1 % of the Fresnel reflectance at
// normal incidence).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

/// The most bands a spectral run holds: a record's band index is one byte.
inline constexpr std::size_t max_spectral_bands = 256;

/// A spectral run's first pass per band and its photon map of all bands.
template <class Store>
struct SpectralWater {
    std::vector<PlaneParallelResult> first_pass;  ///< per band: irradiances, above-surface values (no Lu)
    PhotonMap<Store> map;                         ///< every band's photons; bands() == the wavelengths
};

/// The seed of band k's photons (see the header).
inline std::uint64_t band_seed(std::uint64_t seed, std::size_t band) {
    return seed + 0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(band);
}

/// Traces each band's first pass (media[k] at wavelengths_nm[k]) with cfg's settings and builds
/// one map of all their photons into a Store (store_args: the store's constructor arguments after
/// the records). Events are stored down to cfg.transport.map_depth.
template <class Store, Medium M, class... StoreArgs>
SpectralWater<Store> trace_spectral_map(const std::vector<M>& media, const std::vector<double>& wavelengths_nm,
                                        const PlaneParallelConfig& cfg, const StoreArgs&... store_args) {
    using Record = typename PhotonMap<Store>::Record;
    require(!media.empty() && media.size() <= max_spectral_bands, "bands", media.size(),
            "must be 1 to 256 (a one-byte band index)");
    require_first_pass_fits_in_memory<Record>(cfg.transport, static_cast<double>(media.size()));
    require(wavelengths_nm.size() == media.size(), "wavelengths", wavelengths_nm.size(),
            "must be one per medium (" + std::to_string(media.size()) + ")");
    std::vector<PlaneParallelResult> results;
    std::vector<Estimate> bottom_ed;
    std::vector<Record> records;
    std::optional<RecordFlux> flux;
    std::optional<MapScene> scene;
    unsigned batches = 0;
    for (std::size_t k = 0; k < media.size(); ++k) {
        PlaneParallelConfig band_cfg = cfg;
        band_cfg.transport.band = static_cast<std::uint8_t>(k);
        band_cfg.transport.seed = band_seed(cfg.transport.seed, k);
        auto first = detail::run_first_pass<Record>(media[k], band_cfg, std::chrono::steady_clock::now());
        const RecordFlux& f = first.transport.map_flux;
        if (k == 0) {
            flux = f;
            scene = first.scene;
            batches = first.transport.batches;
        }
        require(std::abs(f.per_record - flux->per_record) <= 1e-12 * flux->per_record, "flux per record",
                f.per_record, "must be the same in every band (band 0: " + std::to_string(flux->per_record) + ")");
        require(!f.importance.enabled(), "depth importance", "on",
                "is not available in a spectral run (each band's levels would differ)");
        require(!f.upward.enabled(), "upward importance", f.upward.share(),
                "is not available in a spectral run (the bands share one map)");
        results.push_back(std::move(first.result));
        bottom_ed.push_back(first.transport.bottom_ed);
        records.insert(records.end(), first.transport.records.begin(), first.transport.records.end());
    }
    return {std::move(results), PhotonMap<Store>::of_bands(Store(std::move(records), store_args...), *flux, batches,
                                                          std::move(*scene), wavelengths_nm, std::move(bottom_ed))};
}

}  // namespace secchi

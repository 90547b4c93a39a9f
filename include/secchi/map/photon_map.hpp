#pragma once
// The photon map as one value: the built store and everything the second pass needs to turn
// the photons it collects into radiance (manual 3.4-3.5):
//  - the flux a record carries, with the depth importance it was stored under and the depth
//    down to which events were stored (transport/record_flux.hpp; manual 3.3.2.4);
//  - the number of independent batches the photons were split into (every estimate's SE);
//  - the scene the photons were traced in: the periodic section and the bottom (scene/slab.hpp),
//    the surface (flat: its refractive index; a wind-blown surface is not modelled by the
//    second pass), the light above the surface (scene/sky_light.hpp), and the first pass's
//    irradiance on the bottom (the Lambertian bottom's radiance A Ed / pi, eq. 3.18's boundary
//    term);
//  - the band list: band k of a record (its band() byte) is wavelength bands()[k].
// Estimators (estimate/path_radiance.hpp, estimate/radiance.hpp) take the map and a collection
// volume and read the rest from it.
//
// Contract: built once (the store's build is the cost), then any number of threads may call its
// const members and run estimators on it at once. The map owns its store and scene; an estimator
// refers to the map, and the estimators' constructors refuse a temporary map (deleted rvalue
// overloads), so no estimator can outlive a map it was built from in one expression.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/scene/flat_surface.hpp"
#include "secchi/scene/sky_light.hpp"
#include "secchi/scene/slab.hpp"
#include "secchi/transport/record_flux.hpp"
#include <algorithm>
#include <cmath>
#include <optional>
#include <ranges>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

/// The scene a map's photons were traced in, as the second pass sees it. Its bottom is an
/// IrradianceBottom (scene/bottom.hpp): the reflected radiance follows from the first pass's Ed
/// on the bottom; a first pass over another bottom model makes no map.
struct MapScene {
    static_assert(IrradianceBottom<Slab::bottom_type>);
    Slab slab;                                ///< periodic section (width) and bottom
    std::optional<FlatSurface> flat_surface;  ///< the flat surface; empty: a surface the second pass does not model
    SkyLight light;                           ///< the sky and the direct sun above the surface

    /// Open water for a map made by hand: infinitely deep, no interface (index 1), black sky, no sun.
    static MapScene open_water(double section_width) {
        return {Slab(section_width, Bottom::infinitely_deep()), FlatSurface(1.0),
                SkyLight([](const vec3&) { return 0.0; }, DirectBeam{})};
    }
};

template <class Store>
class PhotonMap {
public:
    using Record = std::remove_cvref_t<std::ranges::range_reference_t<decltype(std::declval<const Store&>().records())>>;
    static constexpr unsigned max_batches = 256;  ///< as TransportSettings allows

    /// store: built from the records; flux: what a record carries; batches: how many the first
    /// pass split its photons into; bottom_ed: Ed arriving on the bottom (its SE: the first
    /// pass's); wavelengths_nm: one entry per band (one band of unstated wavelength by default).
    PhotonMap(Store store, RecordFlux flux, unsigned batches, MapScene scene, Estimate bottom_ed = {},
              std::vector<double> wavelengths_nm = {NAN})
        : PhotonMap(PerBand{}, std::move(store), flux, batches, std::move(scene),
                    std::vector<Estimate>(std::max<std::size_t>(wavelengths_nm.size(), 1), bottom_ed), std::move(wavelengths_nm)) {}

    /// A map of several bands (a spectral run, solver/spectral.hpp): Ed on the bottom per band.
    /// Every record carries the same flux whatever its band (the manual's 3.3.1.2: photons per
    /// band in proportion to the band's share of the source's flux).
    static PhotonMap of_bands(Store store, RecordFlux flux, unsigned batches, MapScene scene,
                              std::vector<double> wavelengths_nm, std::vector<Estimate> bottom_ed) {
        require(bottom_ed.size() == wavelengths_nm.size(), "bottom Ed per band", bottom_ed.size(),
                "must be one per band (" + std::to_string(wavelengths_nm.size()) + ")");
        return PhotonMap(PerBand{}, std::move(store), flux, batches, std::move(scene), std::move(bottom_ed),
                         std::move(wavelengths_nm));
    }

private:
    struct PerBand {};  // tags the constructor of per-band bottom irradiances
    PhotonMap(PerBand, Store store, RecordFlux flux, unsigned batches, MapScene scene, std::vector<Estimate> bottom_ed,
              std::vector<double> wavelengths_nm)
        : store_(std::move(store)), flux_(flux), batches_(batches), scene_(std::move(scene)), bottom_ed_(std::move(bottom_ed)),
          wavelengths_(std::move(wavelengths_nm)) {
        require(batches >= 1 && batches <= max_batches, "batches", batches, "must be in [1, 256]");
        require(!wavelengths_.empty() && wavelengths_.size() <= 256, "bands", wavelengths_.size(), "must be in [1, 256]");
        for (const Estimate& e : bottom_ed_)
            require(std::isfinite(e.value) && e.value >= 0.0, "bottom Ed", e.value, "must be finite and >= 0");
        // Every record's batch needs its sum and every band its wavelength: once per map, O(N),
        // far below the store's own build.
        unsigned batch = 0, band = 0;
        for (const auto& rec : store_.records()) {
            batch = std::max<unsigned>(batch, rec.batch());
            band = std::max<unsigned>(band, rec.band());
        }
        require(batch < batches, "batches", batches,
                "is fewer than the map's: a stored photon has batch index " + std::to_string(batch) +
                    " (pass the first pass's TransportResult::batches)");
        require(band < wavelengths_.size(), "bands", wavelengths_.size(),
                "are fewer than the map's: a stored photon has band index " + std::to_string(band));
    }

public:

    /// The map of a first pass's result (a TransportResult: records, map_flux, batches,
    /// bottom_ed), its records moved into a Store built with store_args.
    template <class Result, class... StoreArgs>
    static PhotonMap from_first_pass(Result&& result, MapScene scene, StoreArgs&&... store_args) {
        static_assert(!std::is_lvalue_reference_v<Result>, "pass the first pass's result as an rvalue: its records move");
        return PhotonMap(Store(std::move(result.records), std::forward<StoreArgs>(store_args)...), result.map_flux,
                         result.batches, std::move(scene), result.bottom_ed);
    }

    [[nodiscard]] const Store& store() const { return store_; }
    [[nodiscard]] const RecordFlux& flux() const { return flux_; }
    [[nodiscard]] unsigned batches() const { return batches_; }
    [[nodiscard]] const MapScene& scene() const { return scene_; }
    [[nodiscard]] double section_width() const { return scene_.slab.width(); }
    [[nodiscard]] const Bottom& bottom() const { return scene_.slab.bottom(); }
    /// Ed arriving on the bottom in band `band` (0 without one), from the first pass.
    [[nodiscard]] const Estimate& bottom_ed(unsigned band = 0) const { return bottom_ed_.at(band); }
    [[nodiscard]] std::size_t bands() const { return wavelengths_.size(); }
    [[nodiscard]] const std::vector<double>& wavelengths_nm() const { return wavelengths_; }

private:
    Store store_;
    RecordFlux flux_;
    unsigned batches_;
    MapScene scene_;
    std::vector<Estimate> bottom_ed_;  ///< per band
    std::vector<double> wavelengths_;
};

}  // namespace secchi

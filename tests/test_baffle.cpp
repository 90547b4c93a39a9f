// The baffle of manual section 7.3.1 (Figs. 7.1 and 7.2): a detector plane in the water facing
// a uniform unidirectional source, an opaque baffle halfway between them, isotropic
// scattering. The manual's account: light bleeds around the baffle's edges by scattering; the
// centre of its shadow is the darkest; nothing bleeds through the baffle; "only
// multi-scattered paths can reach the detector".
//
// Here: the sun at the zenith through an index-matched surface (no refraction or reflection:
// a unidirectional source of unit plane irradiance), a black bottom at 4 m as the detector
// (its Ed in 30 x 30 bins of 0.2 m over a 6 m section), a black baffle 2 m x 2 m x 0.1 m
// centred 2 m deep (bins 10-19 lie under it), water c = 0.5 1/m. Checked: with w0 = 0 the
// shadow reads exactly 0 (nothing through the baffle); with w0 = 0.9 every bin of the shadow
// is lit, its brightness rises from the centre outward, the ledger closes with what the baffle
// absorbed, and the analog and weighted estimators agree. Against the manual's last claim: the
// singly scattered part of the shadow's centre, computed independently by quadrature, is a
// part of what the tracer finds there, not nothing (single scattering reaches under the
// baffle from the water beside and below it).
#include <catch2/catch.hpp>

#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/scene/shapes.hpp"
#include "secchi/transport/tracer.hpp"
#include "random_draws.hpp"
#include "transport_checks.hpp"
#include <cmath>

using namespace secchi;

namespace {
using IsoWater = HomogeneousWater<IsotropicPhase>;
constexpr double width = 6.0, depth = 4.0, c = 0.5;
constexpr unsigned bins = 30;                                   // 0.2 m
constexpr double lo = 2.0, hi = 4.0, top = 1.95, bottom = 2.05;  // the baffle

TransportResult<CompactRecord> trace_baffle(double albedo, AbsorptionMode mode, std::uint64_t photons) {
    Shapes baffle;
    baffle.add(AxisBox(vec3(lo, lo, top), vec3(hi, hi, bottom)), ObjectMaterial::absorbing());
    TransportSettings s;
    s.photons = photons;
    s.map_photons = 0;
    s.depths = {0.0};
    s.bottom_bins = bins;
    s.absorption = mode;
    s.roulette_weight = 0.0;  // the ledger closes photon by photon
    s.block_size = 5000;
    return PhotonTracer<IsoWater, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, Shapes>(
               IsoWater::from_albedo(c, albedo, IsotropicPhase{}), Slab(width, Bottom::lambertian_at(depth, 0.0)),
               FlatSurface(1.0), SunAndSky(CollimatedSun(0.0)), s, baffle)
        .run();
}

/// Ring of a bin under the baffle: 0 for the four central bins out to 4 for those along its
/// edges; -1 for bins outside its footprint.
int ring(unsigned ix, unsigned iy) {
    if (ix < 10 || ix > 19 || iy < 10 || iy > 19) return -1;
    return static_cast<int>(std::max(std::abs(ix - 14.5), std::abs(iy - 14.5)) - 0.5);
}

/// The mean of the bins for which `pick(ix, iy)` holds, with its SE from the bins' SEs in
/// quadrature: within a batch the bins count disjoint sets of photon arrivals, whose
/// covariances are small and negative (multinomial), so this is the SE to within them.
template <class Pick>
Estimate mean_of(const std::vector<Estimate>& b, Pick pick) {
    double sum = 0.0, se = 0.0, n = 0.0;
    for (unsigned iy = 0; iy < bins; ++iy)
        for (unsigned ix = 0; ix < bins; ++ix)
            if (pick(ix, iy)) {
                sum += b[iy * bins + ix].value;
                se += b[iy * bins + ix].se * b[iy * bins + ix].se;
                n += 1.0;
            }
    return {sum / n, std::sqrt(se) / n};
}

/// Inside the baffle or one of its periodic copies.
bool in_baffle(const vec3& p) {
    const double x = p.x - width * std::floor(p.x / width), y = p.y - width * std::floor(p.y / width);
    return p.z >= top && p.z <= bottom && x >= lo && x <= hi && y >= lo && y <= hi;
}

/// The singly scattered Ed on the bottom over the four central bins ([2.8, 3.2]^2), by
/// quadrature independent of the tracer: Ed1 = int cos(theta) dOmega int_0^s_end
/// (b / 4 pi) exp(-c z(s)) V(x(s)) exp(-c s) ds over the upward hemisphere from a point P of
/// the bins, with X = P + s w the scattering point, exp(-c z) the unit beam reaching it through
/// the water (V = 0 where the baffle shades it: X under a copy's footprint, below its top) and
/// s_end where the ray from P leaves the water or enters a baffle. Directions cosine-weighted
/// (Ed1 = pi E[L1]) and P uniform over the bins; the path integral by the midpoint rule with a
/// random offset per ray (unbiased for the indicator), 5 mm steps, to exp(-c s) < 1e-9.
Estimate single_scattering_at_centre(std::uint64_t samples) {
    testing::Rand r(71);
    const double b = 0.9 * c, ds = 0.005, s_max = -std::log(1e-9) / c;
    double sum = 0.0, sum2 = 0.0;
    for (std::uint64_t k = 0; k < samples; ++k) {
        const vec3 p{r.in(2.8, 3.2), r.in(2.8, 3.2), depth};
        const double mu = std::sqrt(r()), phi = two_pi * r(), sin = std::sqrt(1.0 - mu * mu);
        const vec3 w{sin * std::cos(phi), sin * std::sin(phi), -mu};  // upward: z decreasing
        double path = 0.0;
        for (double s = r() * ds; s < s_max; s += ds) {
            const vec3 x = p + s * w;
            if (x.z <= 0.0 || in_baffle(x)) break;
            const bool shaded = x.z > bottom && in_baffle(vec3(x.x, x.y, top));
            if (!shaded) path += b / (4.0 * pi) * std::exp(-c * (x.z + s)) * ds;
        }
        const double ed = pi * path;
        sum += ed;
        sum2 += ed * ed;
    }
    const double n = static_cast<double>(samples), mean = sum / n;
    return {mean, std::sqrt((sum2 / n - mean * mean) / (n - 1.0))};
}
}  // namespace

TEST_CASE("Baffle (manual 7.3.1): without scattering nothing reaches its shadow, through it or round it") {
    const auto r = trace_baffle(0.0, AbsorptionMode::continuous, 100000);
    for (unsigned iy = 0; iy < bins; ++iy)
        for (unsigned ix = 0; ix < bins; ++ix) {
            const Estimate& e = r.bottom_ed_bins[iy * bins + ix];
            INFO("bin " << ix << ", " << iy << ": " << e.value);
            if (ring(ix, iy) >= 0) CHECK(e.value == 0.0);
            else CHECK(e.value > 0.0);
        }
    CHECK(std::abs(r.ledger.imbalance()) <= 1e-12 * r.ledger.incident);
}

TEST_CASE("Baffle (manual 7.3.1): with isotropic scattering light bleeds round the edges and the centre is darkest") {
    static const auto weighted = trace_baffle(0.9, AbsorptionMode::continuous, 1600000);  // once for both sections
    const auto& b = weighted.bottom_ed_bins;
    // Every bin of the shadow is lit.
    for (unsigned iy = 10; iy <= 19; ++iy)
        for (unsigned ix = 10; ix <= 19; ++ix) CHECK(b[iy * bins + ix].value > 0.0);
    // From the centre outward: inner (rings 0-1), middle (2-3), outer (4) rings of the shadow,
    // then the open bottom (farther than 0.8 m from the footprint), each brighter than the last
    // by more than 3 of their combined SEs.
    const Estimate inner = mean_of(b, [](unsigned x, unsigned y) { const int k = ring(x, y); return k == 0 || k == 1; });
    const Estimate middle = mean_of(b, [](unsigned x, unsigned y) { const int k = ring(x, y); return k == 2 || k == 3; });
    const Estimate outer = mean_of(b, [](unsigned x, unsigned y) { return ring(x, y) == 4; });
    const Estimate open = mean_of(b, [](unsigned x, unsigned y) { return x < 6 || x > 23 || y < 6 || y > 23; });
    INFO("shadow inner " << inner.value << " +- " << inner.se << ", middle " << middle.value << " +- " << middle.se
                         << ", outer " << outer.value << " +- " << outer.se << "; open bottom " << open.value << " +- "
                         << open.se);
    CHECK(middle.value - inner.value > 3.0 * std::hypot(inner.se, middle.se));
    CHECK(outer.value - middle.value > 3.0 * std::hypot(middle.se, outer.se));
    CHECK(open.value - outer.value > 3.0 * std::hypot(outer.se, open.se));
    // The ledger closes with what the baffle absorbed.
    CHECK(weighted.ledger.absorbed_objects > 0.05 * weighted.ledger.incident);
    CHECK(std::abs(weighted.ledger.imbalance()) <= 1e-9 * weighted.ledger.incident);

    SECTION("the analog estimator finds the same shadow") {
        const auto analog = trace_baffle(0.9, AbsorptionMode::analog, 400000);
        CHECK(std::abs(analog.ledger.imbalance()) <= 1e-9 * analog.ledger.incident);
        const auto& a = analog.bottom_ed_bins;
        testing::check_agree(inner, mean_of(a, [](unsigned x, unsigned y) { const int k = ring(x, y); return k == 0 || k == 1; }), "inner");
        testing::check_agree(outer, mean_of(a, [](unsigned x, unsigned y) { return ring(x, y) == 4; }), "outer");
        testing::check_agree(weighted.bottom_ed, analog.bottom_ed, "bottom Ed");
    }
    SECTION("single scattering reaches the shadow's centre: a part of its light, not all and not none") {
        const Estimate centre = mean_of(b, [](unsigned x, unsigned y) { return ring(x, y) == 0; });
        const Estimate single = single_scattering_at_centre(200000);
        INFO("shadow centre: tracer (all orders) " << centre.value << " +- " << centre.se << ", single scattering "
                                                  << single.value << " +- " << single.se << ", share "
                                                  << single.value / centre.value);
        CHECK(single.value > 4.0 * single.se);                                          // not none
        CHECK(centre.value - single.value > 4.0 * std::hypot(centre.se, single.se));  // higher orders add light
    }
}

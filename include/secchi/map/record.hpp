#pragma once
// Photon records: what the first pass stores at each scattering event (manual 3.3.2).
// Flux is implicit: every stored photon carries Phi_source / photons_shot (manual 3.3.2.4).
// Two policies behind one concept:
//  - CompactRecord: 16 bytes. Position as float3 (3.3.2.1) on a grid of 2^-20 m (below), direction as two bytes (theta,
//    phi, Jensen's encoding, 3.3.2.2), band index one byte (3.3.2.5), and one byte holding the
//    batch index (the independent batch the photon belongs to, for standard errors; up to 64)
//    and two bits a store may use (the k-d tree keeps its split axis there, as Jensen does).
//  - FullRecord: double position and direction; the reference the compact one is tested against.
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include "secchi/core/spectral.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>

namespace secchi::SECCHI_ISA {

template <class R>
concept PhotonRecord = std::copyable<R> && requires(const R r, vec3 p, vec3 d, band_index b, std::uint8_t batch) {
    { R::make(p, d, b, batch) } -> std::same_as<R>;
    { r.position() } -> std::convertible_to<vec3>;   ///< where it scattered
    { r.direction() } -> std::convertible_to<vec3>;  ///< unit direction of travel before scattering
    { r.band() } -> std::convertible_to<band_index>;
    { r.batch() } -> std::convertible_to<std::uint8_t>;
};

/// A record with two spare bits for its store: Jensen (2001, ch. 6) keeps the k-d tree's
/// split axis inside the photon, so the tree costs no memory beside the records.
template <class R>
concept TaggedRecord = PhotonRecord<R> && requires(R r, const R c, std::uint8_t tag) {
    r.set_store_tag(tag);  ///< tag in [0, 3]
    { c.store_tag() } -> std::convertible_to<int>;
};

/// The number of batches a record type can label (R::max_batches if it says, else 256).
template <class R>
constexpr unsigned record_max_batches() {
    if constexpr (requires { R::max_batches; }) return R::max_batches;
    else return 256;
}

/// CompactRecord's position grid, m: every coordinate it stores is a multiple of 2^-20 m
/// (0.95 um; collection radii are millimetres to decimetres). Floats are that coarse from
/// 8 m out (position_grid_limit); nearer the origin, where they are finer, a
/// coordinate is rounded to the nearest multiple (by at most 2^-21 m, 0.48 um). A store may
/// then pack positions as 21-bit integers in frames up to 2 m wide without losing a bit
/// (map/packed_records.hpp).
inline constexpr double position_grid = 0x1p-20;
/// From this magnitude on floats are at least as coarse as position_grid: 2^23 position_grid (8 m).
inline constexpr double position_grid_limit = 0x1p23 * position_grid;

namespace detail {
/// A coordinate as CompactRecord stores it: the nearest multiple of position_grid for |c| <
/// position_grid_limit (exact in float: fewer than 2^23 steps; a zero is +0, as the packed
/// layout reads it back), else the nearest float (itself a multiple).
inline float grid_coordinate(double c) {
    return std::abs(c) < position_grid_limit ? static_cast<float>(std::nearbyint(c / position_grid) * position_grid + 0.0)
                                              : static_cast<float>(c);
}

/// Decoding tables for the two-byte direction: theta in [0, pi], phi in [0, 2 pi).
struct DirectionTables {
    std::array<double, 256> cos_theta{}, sin_theta{}, cos_phi{}, sin_phi{};
    DirectionTables() {
        for (int i = 0; i < 256; ++i) {
            const double theta = (i + 0.5) * pi / 256.0;  // bin centres
            const double phi = i * two_pi / 256.0;
            cos_theta[i] = std::cos(theta);
            sin_theta[i] = std::sin(theta);
            cos_phi[i] = std::cos(phi);
            sin_phi[i] = std::sin(phi);
        }
    }
};
inline const DirectionTables& direction_tables() {
    static const DirectionTables tables;
    return tables;
}

/// Encoding tables: the bin boundaries. theta_edge[k] = cos(k pi/256) (k = 1..255; +inf at
/// k = 0 and -inf at k = 256, so the correction steps below never leave [0, 255]);
/// phi_edge_{cos,sin}[j]: the unit vector at azimuth (j + 1/2) 2 pi/256, between bins j and j+1.
struct DirectionEncodeTables {
    std::array<double, 257> theta_edge{};
    std::array<double, 256> phi_edge_cos{}, phi_edge_sin{};
    DirectionEncodeTables() {
        theta_edge[0] = INFINITY;
        theta_edge[256] = -INFINITY;
        for (int k = 1; k < 256; ++k) theta_edge[k] = std::cos(k * pi / 256.0);
        for (int j = 0; j < 256; ++j) {
            phi_edge_cos[j] = std::cos((j + 0.5) * two_pi / 256.0);
            phi_edge_sin[j] = std::sin((j + 0.5) * two_pi / 256.0);
        }
    }
};
inline const DirectionEncodeTables& direction_encode_tables() {
    static const DirectionEncodeTables tables;
    return tables;
}

/// The theta byte floor(acos(dz) 256/pi) (255 at dz = -1) without acos. As acos decreases,
/// it is the number of boundaries k pi/256 (k = 1..255) with dz <= cos(k pi/256). A guess from
/// Abramowitz and Stegun 4.4.45 (acos x = sqrt(1 - x) (a0 + a1 x + a2 x^2 + a3 x^3), error
/// < 7e-5 rad = 0.006 bin for 0 <= x <= 1; acos(-x) = pi - acos x) is within one bin of the
/// answer, and one comparison with each neighbouring boundary makes it exact.
inline int encode_theta(double dz) {
    const auto& t = direction_encode_tables();
    double x = std::abs(dz);
    x = x < 1.0 ? x : 1.0;  // also maps NaN to a valid bin
    const double acos_x = std::sqrt(1.0 - x) * (1.5707288 + x * (-0.2121144 + x * (0.0742610 - 0.0187293 * x)));
    const double theta = dz < 0.0 ? pi - acos_x : acos_x;
    int k = std::min(255, static_cast<int>(theta * (256.0 / pi)));
    k += dz <= t.theta_edge[k + 1];  // theta at or past the upper boundary
    k -= dz > t.theta_edge[k];       // theta before the lower boundary
    return k;
}

/// The phi byte lround(atan2(dy, dx) 256/(2 pi)) & 255 (atan2 taken in [0, 2 pi)) without
/// atan2: bin j holds azimuths in [(j - 1/2), (j + 1/2)) 2 pi/256. A guess from an octant-
/// reduced atan(t) ~ pi/4 t - t (t - 1)(0.2447 + 0.0663 t) (error < 0.0015 rad = 0.07 bin) is
/// within one bin of the answer; the side of each neighbouring boundary b is the sign of the
/// cross product b x d = r sin(phi - phi_b), exact up to rounding (~1e-16 rad) because
/// |phi - phi_b| < pi. At the poles (dx = dy = 0) it returns atan2's choice: 0, or 128 for dx = -0.
inline int encode_phi(double dx, double dy) {
    if (dx == 0.0 && dy == 0.0) return std::signbit(dx) ? 128 : 0;
    const auto& t = direction_encode_tables();
    const double ax = std::abs(dx), ay = std::abs(dy);
    const double r = std::min(ax, ay) / std::max(ax, ay);
    double a = r * (0.25 * pi - (r - 1.0) * (0.2447 + 0.0663 * r));  // atan(r), r in [0, 1]
    if (ay > ax) a = 0.5 * pi - a;
    if (dx < 0.0) a = pi - a;
    if (dy < 0.0) a = two_pi - a;
    int j = static_cast<int>(a * (256.0 / two_pi) + 0.5) & 255;
    const int below = (j - 1) & 255;
    if (t.phi_edge_cos[j] * dy - t.phi_edge_sin[j] * dx >= 0.0) j = (j + 1) & 255;  // at or past the upper boundary
    else if (t.phi_edge_cos[below] * dy - t.phi_edge_sin[below] * dx < 0.0) j = below;  // before the lower one
    return j;
}
}  // namespace detail

/// 16-byte record. Direction quantisation: theta to pi/256 (max error 0.35 deg), phi to
/// 2 pi/256 (max error 0.70 deg of azimuth, less in angle away from the poles).
struct CompactRecord {
    float x, y, z;
    std::uint8_t theta, phi;
    band_index band_;
    std::uint8_t batch_;  ///< the batch (low 6 bits) and the store's tag (high 2 bits)

    static constexpr unsigned max_batches = 64;

    /// Coordinates: detail::grid_coordinate (multiples of position_grid).
    /// theta = floor(acos(dz) 256/pi) (at most 255), phi = lround(atan2(dy, dx) 256/(2 pi)) mod
    /// 256, computed without acos and atan2 (detail::encode_theta, encode_phi): the bytes
    /// equal those of the formula, except where the angle lies within rounding (~1e-14 rad)
    /// of a bin boundary, where either side is as good.
    static CompactRecord make(const vec3& p, const vec3& d, band_index b, std::uint8_t batch) {
        return {detail::grid_coordinate(p.x), detail::grid_coordinate(p.y), detail::grid_coordinate(p.z),
                static_cast<std::uint8_t>(detail::encode_theta(d.z)), static_cast<std::uint8_t>(detail::encode_phi(d.x, d.y)),
                b, batch};
    }
    [[nodiscard]] vec3 position() const { return {x, y, z}; }
    /// Decoded per photon in the second pass's loops: always inlined (SECCHI_KERNEL).
    [[nodiscard]] SECCHI_KERNEL vec3 direction() const {
        const auto& t = detail::direction_tables();
        return {t.sin_theta[theta] * t.cos_phi[phi], t.sin_theta[theta] * t.sin_phi[phi], t.cos_theta[theta]};
    }
    [[nodiscard]] band_index band() const { return band_; }
    [[nodiscard]] std::uint8_t batch() const { return batch_ & 63u; }
    [[nodiscard]] int store_tag() const { return batch_ >> 6; }
    void set_store_tag(std::uint8_t tag) { batch_ = static_cast<std::uint8_t>((batch_ & 63u) | (tag << 6)); }
};
static_assert(sizeof(CompactRecord) == 16, "the compact record must stay 16 bytes");

/// The polar code of a record type: a byte k with direction().z == cosine(k) exactly (the
/// second pass tabulates per vertical ray what depends on it: estimate/path_radiance.hpp).
/// Specialised for the records that have one; the primary template says "none".
template <class R>
struct PolarCode {};

/// CompactRecord's theta byte: its direction() has z = the decoding table's cos_theta[theta].
template <>
struct PolarCode<CompactRecord> {
    static std::uint8_t of(const CompactRecord& r) { return r.theta; }
    static double cosine(std::uint8_t k) { return detail::direction_tables().cos_theta[k]; }
};

template <class R>
concept PolarCodedRecord = PhotonRecord<R> && requires(const R r, std::uint8_t k) {
    { PolarCode<R>::of(r) } -> std::same_as<std::uint8_t>;
    { PolarCode<R>::cosine(k) } -> std::same_as<double>;
};

/// Full-precision record (40 bytes): exact position and direction.
struct FullRecord {
    vec3 pos;
    vec3 dir;
    band_index band_;
    std::uint8_t batch_;

    static FullRecord make(const vec3& p, const vec3& d, band_index b, std::uint8_t batch) {
        return {p, d, b, batch};
    }
    [[nodiscard]] vec3 position() const { return pos; }
    [[nodiscard]] vec3 direction() const { return dir; }
    [[nodiscard]] band_index band() const { return band_; }
    [[nodiscard]] std::uint8_t batch() const { return batch_; }
};

static_assert(PhotonRecord<CompactRecord>);
static_assert(PhotonRecord<FullRecord>);
static_assert(TaggedRecord<CompactRecord>);

}  // namespace secchi

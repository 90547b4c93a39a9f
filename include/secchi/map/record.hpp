#pragma once
// Photon records: what the first pass stores at each scattering event (manual 3.3.2).
// Flux is implicit: every stored photon carries Phi_source / photons_shot (manual 3.3.2.4).
// Two policies behind one concept:
//  - CompactRecord: 16 bytes. Position as float3 (3.3.2.1), direction as two bytes (theta,
//    phi, Jensen's encoding, 3.3.2.2), band index one byte (3.3.2.5), batch index one byte
//    (the independent batch the photon belongs to, for standard errors).
//  - FullRecord: double position and direction; the reference the compact one is tested against.
#include "secchi/core/math.hpp"
#include "secchi/core/spectral.hpp"
#include <algorithm>
#include <array>
#include <concepts>
#include <cstdint>

namespace secchi {

template <class R>
concept PhotonRecord = std::copyable<R> && requires(const R r, vec3 p, vec3 d, band_index b, std::uint8_t batch) {
    { R::make(p, d, b, batch) } -> std::same_as<R>;
    { r.position() } -> std::convertible_to<vec3>;   ///< where it scattered
    { r.direction() } -> std::convertible_to<vec3>;  ///< unit direction of travel before scattering
    { r.band() } -> std::convertible_to<band_index>;
    { r.batch() } -> std::convertible_to<std::uint8_t>;
};

namespace detail {
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
}  // namespace detail

/// 16-byte record. Direction quantisation: theta to pi/256 (max error 0.35 deg), phi to
/// 2 pi/256 (max error 0.70 deg of azimuth, less in angle away from the poles).
struct CompactRecord {
    float x, y, z;
    std::uint8_t theta, phi;
    band_index band_;
    std::uint8_t batch_;

    static CompactRecord make(const vec3& p, const vec3& d, band_index b, std::uint8_t batch) {
        const double theta = std::acos(std::clamp(d.z, -1.0, 1.0));
        double phi = std::atan2(d.y, d.x);
        if (phi < 0.0) phi += two_pi;
        const int ti = std::min(255, static_cast<int>(theta * 256.0 / pi));
        const int pj = static_cast<int>(std::lround(phi * 256.0 / two_pi)) & 255;
        return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z),
                static_cast<std::uint8_t>(ti), static_cast<std::uint8_t>(pj), b, batch};
    }
    [[nodiscard]] vec3 position() const { return {x, y, z}; }
    [[nodiscard]] vec3 direction() const {
        const auto& t = detail::direction_tables();
        return {t.sin_theta[theta] * t.cos_phi[phi], t.sin_theta[theta] * t.sin_phi[phi], t.cos_theta[theta]};
    }
    [[nodiscard]] band_index band() const { return band_; }
    [[nodiscard]] std::uint8_t batch() const { return batch_; }
};
static_assert(sizeof(CompactRecord) == 16, "the compact record must stay 16 bytes");

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

}  // namespace secchi

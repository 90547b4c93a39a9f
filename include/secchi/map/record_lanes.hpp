#pragma once
// Records for a vector of scattering events at once (photons in lanes,
// transport/lane_tracer.hpp). LaneRecords<R>::make(p, d, band, batch, out) writes
// out[l] = R::make(p_l, d_l, band, batch[l]) for every lane l. A record type without a
// specialisation is made lane by lane; CompactRecord's direction bytes are encoded in the
// vectors by the guess-and-correct of detail::encode_theta and encode_phi (record.hpp), the
// same operations without a branch, so the bytes equal make()'s (tests/test_lane_tracer.cpp).
#include "secchi/core/lanes.hpp"
#include "secchi/map/record.hpp"

#if SECCHI_HAS_LANES
namespace secchi {

template <class Record>
struct LaneRecords {
    static void make(const lanes::Vec3& p, const lanes::Vec3& d, band_index band, const std::uint8_t* batch,
                     Record* out) {
        for (int l = 0; l < lanes::lane_width; ++l)
            out[l] = Record::make(vec3(p.x[l], p.y[l], p.z[l]), vec3(d.x[l], d.y[l], d.z[l]), band, batch[l]);
    }
};

namespace detail {
/// encode_theta per lane (the byte as a double).
SECCHI_LANE_KERNEL lanes::Reals encode_theta(const lanes::Reals& dz) {
    using lanes::Reals;
    const auto& t = direction_encode_tables();
    const Reals abs_dz = lanes::stdx::abs(dz);
    const Reals x = select(abs_dz < 1.0, abs_dz, Reals(1.0));
    const Reals acos_x = lanes::stdx::sqrt(1.0 - x) * (1.5707288 + x * (-0.2121144 + x * (0.0742610 - 0.0187293 * x)));
    const Reals theta = select(dz < 0.0, pi - acos_x, acos_x);
    Reals k = lanes::stdx::min(Reals(255.0), lanes::stdx::floor(theta * (256.0 / pi)));
    lanes::stdx::where(dz <= lanes::lookup(t.theta_edge, k + 1.0), k) += 1.0;  // at or past the upper boundary
    lanes::stdx::where(dz > lanes::lookup(t.theta_edge, k), k) -= 1.0;         // before the lower boundary
    return k;
}

/// encode_phi per lane (the byte as a double).
SECCHI_LANE_KERNEL lanes::Reals encode_phi(const lanes::Reals& dx, const lanes::Reals& dy) {
    using lanes::Reals;
    const auto& t = direction_encode_tables();
    const auto pole = dx == 0.0 && dy == 0.0;
    const Reals ax = lanes::stdx::abs(dx), ay = lanes::stdx::abs(dy);
    const Reals r = select(pole, Reals(0.0), lanes::stdx::min(ax, ay) / lanes::stdx::max(ax, ay));
    Reals a = r * (0.25 * pi - (r - 1.0) * (0.2447 + 0.0663 * r));  // atan(r), r in [0, 1]
    a = select(ay > ax, 0.5 * pi - a, a);
    a = select(dx < 0.0, pi - a, a);
    a = select(dy < 0.0, two_pi - a, a);
    Reals j = lanes::stdx::floor(a * (256.0 / two_pi) + 0.5);  // a >= 0: the truncation of encode_phi
    j = select(j >= 256.0, j - 256.0, j);
    const Reals below = select(j == 0.0, Reals(255.0), j - 1.0), above = select(j == 255.0, Reals(0.0), j + 1.0);
    const auto past_upper = lanes::lookup(t.phi_edge_cos, j) * dy - lanes::lookup(t.phi_edge_sin, j) * dx >= 0.0;
    const auto before_lower = lanes::lookup(t.phi_edge_cos, below) * dy - lanes::lookup(t.phi_edge_sin, below) * dx < 0.0;
    j = select(past_upper, above, select(before_lower, below, j));
    // At the poles, atan2's choice: 0, or 128 for dx = -0.
    return select(pole, select(lanes::stdx::copysign(Reals(1.0), dx) < 0.0, Reals(128.0), Reals(0.0)), j);
}
}  // namespace detail

template <>
struct LaneRecords<CompactRecord> {
    static void make(const lanes::Vec3& p, const lanes::Vec3& d, band_index band, const std::uint8_t* batch,
                     CompactRecord* out) {
        const lanes::Reals theta = detail::encode_theta(d.z), phi = detail::encode_phi(d.x, d.y);
        for (int l = 0; l < lanes::lane_width; ++l)
            out[l] = {static_cast<float>(p.x[l]), static_cast<float>(p.y[l]), static_cast<float>(p.z[l]),
                      static_cast<std::uint8_t>(theta[l]), static_cast<std::uint8_t>(phi[l]), band, batch[l]};
    }
};

}  // namespace secchi
#endif

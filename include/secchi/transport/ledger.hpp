#pragma once
// Energy accounting of the first pass: every photon's weight ends in exactly one account,
// so incident = surface_reflected + escaped_up + to_space + absorbed_air + absorbed +
// absorbed_bottom + absorbed_objects + transmitted + truncated + roulette_killed -
// roulette_gained. In analog mode the roulette terms are zero; with weighted photons every
// change of the total weight (Russian roulette, backscatter bias; a split keeps it) is booked
// where it is made, so the balance holds to rounding either way (roulette_gained and
// roulette_killed are equal in expectation only). Under a source that sends light back (a
// traced atmosphere, scene/atmosphere.hpp) light going up from the surface is handed to it, so
// it ends in to_space or absorbed_air, and surface_reflected and escaped_up stay 0; under one
// that does not (a sun and a sky above the surface) to_space and absorbed_air stay 0.
#include "secchi/core/config.hpp"
#include <array>
#include <cstddef>
namespace secchi::SECCHI_ISA {

struct EnergyLedger {
    double incident = 0;           ///< weight that the source emitted (at the surface, or at the top of an atmosphere)
    double surface_reflected = 0;  ///< specular reflection of the incident beam
    double escaped_up = 0;         ///< left the water upward through the surface
    double to_space = 0;           ///< left the top of a traced atmosphere
    double absorbed_air = 0;       ///< absorbed in a traced atmosphere
    double absorbed = 0;           ///< absorbed in the water
    double absorbed_bottom = 0;    ///< absorbed by an opaque bottom
    double absorbed_objects = 0;   ///< absorbed by objects in the water (scene/geometry.hpp)
    double transmitted = 0;        ///< left through the bottom of a finite slab, or below the escape depth
    double truncated = 0;          ///< stopped by the scattering-order limit (manual 3.3.8)
    double roulette_killed = 0;    ///< weight removed by Russian roulette (and by backscatter bias's weights below 1)
    double roulette_gained = 0;    ///< weight added to roulette survivors (and by backscatter bias's weights above 1)

    static constexpr std::size_t accounts = 12;  ///< the number of accounts

private:
    template <class Self>  // EnergyLedger or const EnergyLedger
    static auto pointers(Self& l) {
        return std::array{&l.incident,        &l.surface_reflected, &l.escaped_up,  &l.to_space,
                          &l.absorbed_air,    &l.absorbed,          &l.absorbed_bottom, &l.absorbed_objects,
                          &l.transmitted,     &l.truncated,         &l.roulette_killed, &l.roulette_gained};
    }

public:
    /// Every account, in one fixed order, for code that treats them alike (sums, normalising,
    /// sending them between processes).
    [[nodiscard]] std::array<double*, accounts> entries() { return pointers(*this); }
    [[nodiscard]] std::array<double, accounts> values() const {
        std::array<double, accounts> v{};
        const auto p = pointers(*this);
        for (std::size_t i = 0; i < accounts; ++i) v[i] = *p[i];
        return v;
    }

    EnergyLedger& operator+=(const EnergyLedger& o) {
        const auto mine = entries();
        const auto theirs = o.values();
        for (std::size_t i = 0; i < accounts; ++i) *mine[i] += theirs[i];
        return *this;
    }
    /// incident minus everything accounted for; 0 up to rounding in analog mode.
    [[nodiscard]] double imbalance() const {
        return incident + roulette_gained -
               (surface_reflected + escaped_up + to_space + absorbed_air + absorbed + absorbed_bottom + absorbed_objects + transmitted +
                truncated + roulette_killed);
    }
};

}  // namespace secchi

#pragma once
// The radiance distribution at a depth of a plane-parallel water body, from the photon map
// (estimate/radiance.hpp: the whole radiance along a ray), and the irradiances it integrates to
// (Mobley 1994, "Light and Water", sec. 1.4; M93 Table 1):
//     Ed  = int_down L |mu| dOmega,  Eod = int_down L dOmega   (light travelling down: rays looking up)
//     Eu  = int_up   L |mu| dOmega,  Eou = int_up   L dOmega   (light travelling up: rays looking down)
// each including the direct sun's beam where it travels (Ed += E_perp mu_w, Eod += E_perp).
//
// radiance_distribution(): a latitude-longitude grid of the radiance seen looking along each
// direction (row 0 straight up, the last row straight down; column k at look azimuth
// 2 pi (k + 1/2) / columns), each cell the mean over rays of jittered directions within the
// cell and origins spread over the section (the water is horizontally homogeneous).
//
// irradiances_from_map(): the integrals by stratified Monte Carlo over directions: G groups,
// each with one jittered direction per cell of an n_mu x n_phi grid in (|mu|, phi) on each
// hemisphere (uniform in solid angle: |mu| uniform), and a random origin in the section per
// ray. The estimate is the mean over groups; its variance has two sources, the photons
// (batches) and the directions (groups), estimated together from the group x batch table v_gb
// of estimates (a two-way layout: v_gb = m + a_g + b_b + e_gb):
//     Var(mean) = s_g^2 / G + s_b^2 / B - s_e^2 / (G B)
// with s_g^2, s_b^2 the variances of the group means and of the batch means and s_e^2 the
// residual variance, plus the bottom term's shared SE.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/image.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/estimate/radiance.hpp"
#include "secchi/estimate/render.hpp"
#include "secchi/transport/irradiance_planes.hpp"
#include "secchi/core/parallel.hpp"
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace secchi::SECCHI_ISA {

/// How irradiances_from_map samples directions.
struct DirectionSampling {
    unsigned mu_strata = 24;   ///< cells in |mu| per hemisphere
    unsigned phi_strata = 16;  ///< cells in azimuth
    unsigned groups = 8;       ///< independent replicates (>= 2): the directions' share of the SE
    std::uint64_t seed = 1;
};

/// Ed, Eu, Eod, Eou (IrradianceKind order) at one depth, from the map's radiance distribution.
struct MapIrradiances {
    std::array<Estimate, 4> irradiance{};
    std::array<double, 4> direct{};  ///< the direct sun's part of each (in the value; exact)
};

namespace detail {
/// SE of the mean of a groups x batches table (row-major), by the two-way layout above.
inline double two_way_se(const std::vector<double>& v, std::size_t groups, std::size_t batches) {
    std::vector<double> row(groups, 0.0), col(batches, 0.0);
    double mean = 0.0;
    for (std::size_t g = 0; g < groups; ++g)
        for (std::size_t b = 0; b < batches; ++b) {
            const double x = v[g * batches + b];
            row[g] += x / static_cast<double>(batches);
            col[b] += x / static_cast<double>(groups);
            mean += x;
        }
    mean /= static_cast<double>(groups * batches);
    const auto variance = [&](const std::vector<double>& m) {
        double s = 0.0;
        for (double x : m) s += (x - mean) * (x - mean);
        return s / static_cast<double>(m.size() - 1);
    };
    double residual = 0.0;
    for (std::size_t g = 0; g < groups; ++g)
        for (std::size_t b = 0; b < batches; ++b) {
            const double e = v[g * batches + b] - row[g] - col[b] + mean;
            residual += e * e;
        }
    residual /= static_cast<double>((groups - 1) * (batches - 1));
    const double g = static_cast<double>(groups), b = static_cast<double>(batches);
    return std::sqrt(std::max(0.0, variance(row) / g + variance(col) / b - residual / (g * b)));
}

/// The unit vector at polar cosine mu of the look direction (z positive down) and azimuth phi.
inline vec3 look_direction(double mu_z, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - mu_z * mu_z));
    return {s * std::cos(phi), s * std::sin(phi), mu_z};
}
}  // namespace detail

template <class Estimator>
MapIrradiances irradiances_from_map(const Estimator& est, double depth, const DirectionSampling& sampling,
                                    unsigned threads) {
    require(sampling.groups >= 2, "direction groups", sampling.groups, "must be >= 2 (their scatter is part of the SE)");
    require(sampling.mu_strata >= 1 && sampling.phi_strata >= 1, "direction strata", sampling.mu_strata * sampling.phi_strata,
            "must be >= 1 in mu and in phi");
    const auto& map = est.map();
    const double width = map.section_width();
    const unsigned batches = map.batches(), cells = sampling.mu_strata * sampling.phi_strata;
    const double cell_solid_angle = two_pi / cells;  // each hemisphere's 2 pi sr in equal cells

    // Group g, cell i: one ray looking up (light travelling down) and one looking down.
    std::vector<std::array<RadianceSum, 4>> sums(sampling.groups, {RadianceSum(batches), RadianceSum(batches),
                                                                   RadianceSum(batches), RadianceSum(batches)});
    parallel_for(sampling.groups, threads, [&](std::size_t g) {
        PhotonRng rng(sampling.seed, g);
        auto& s = sums[g];
        for (unsigned i = 0; i < cells; ++i) {
            const double mu = (i / sampling.phi_strata + rng.uniform()) / sampling.mu_strata;
            const double phi = two_pi * (i % sampling.phi_strata + rng.uniform()) / sampling.phi_strata;
            const vec3 origin{width * rng.uniform(), width * rng.uniform(), depth};
            for (const bool looking_up : {true, false}) {
                RadianceSum one(batches);
                est.add(Ray{origin, detail::look_direction(looking_up ? -mu : mu, phi), INFINITY}, 0, 1.0, one);
                const int plane = looking_up ? Ed : Eu, scalar = looking_up ? Eod : Eou;
                s[plane].merge(one, cell_solid_angle * mu);
                s[scalar].merge(one, cell_solid_angle);
            }
        }
    });

    MapIrradiances out;
    const DirectBeam sun = est.direct_sun({0.5 * width, 0.5 * width, depth});
    out.direct[Ed] = sun.e_perp * sun.direction.z;
    out.direct[Eod] = sun.e_perp;
    for (int k = 0; k < 4; ++k) {
        RadianceSum total(batches);
        std::vector<double> table;
        table.reserve(static_cast<std::size_t>(sampling.groups) * batches);
        for (const auto& s : sums) {
            total.merge(s[k], 1.0 / sampling.groups);
            for (double v : s[k].per_batch()) table.push_back(v + s[k].outside_batches());
        }
        const double se = std::hypot(detail::two_way_se(table, sampling.groups, batches), total.shared_se());
        out.irradiance[k] = {total.estimate().value + out.direct[k], se};
    }
    return out;
}

/// How radiance_distribution samples each cell.
struct DistributionSettings {
    int columns = 360;          ///< look azimuth cells over [0, 2 pi)
    int rows = 180;             ///< look polar angle cells over [0, pi]: row 0 straight up
    unsigned rays_per_cell = 4; ///< jittered over the cell, each from its own origin in the section
    unsigned threads = 1;
    std::uint64_t seed = 1;
};

/// The radiance seen looking along each direction at `depth` (z < 0: above the water), as a
/// latitude-longitude image (render.hpp's channels): cell (column k, row j) holds the mean of
/// rays_per_cell rays of look polar angle in [pi j / rows, pi (j + 1) / rows) from straight up
/// (z = -1) and azimuth in [2 pi k / columns, 2 pi (k + 1) / columns), jittered, each from a
/// random origin in the section (the water is horizontally homogeneous; that spreads the rays
/// over the map's photons). The direct sun is not in it (direct_sun()).
template <class Estimator>
Image radiance_distribution(const Estimator& est, double depth, const DistributionSettings& settings = {}) {
    require(settings.rays_per_cell >= 1, "rays per cell", settings.rays_per_cell, "must be >= 1");
    const auto& map = est.map();
    const double width = map.section_width();
    return detail::radiance_image(settings.columns, settings.rows, map.wavelengths_nm(), settings.threads,
                                  [&](std::size_t i, unsigned band) {
                                      const std::size_t k = i % static_cast<std::size_t>(settings.columns);
                                      const std::size_t j = i / static_cast<std::size_t>(settings.columns);
                                      PhotonRng rng(settings.seed, i);
                                      RadianceSum sum(map.batches());
                                      for (unsigned s = 0; s < settings.rays_per_cell; ++s) {
                                          const double theta = pi * (static_cast<double>(j) + rng.uniform()) / settings.rows;
                                          const double phi = two_pi * (static_cast<double>(k) + rng.uniform()) / settings.columns;
                                          const vec3 origin{width * rng.uniform(), width * rng.uniform(), depth};
                                          est.add(Ray{origin, detail::look_direction(-std::cos(theta), phi), INFINITY}, band, 1.0, sum);
                                      }
                                      return sum.estimate(settings.rays_per_cell);
                                  });
}

}  // namespace secchi

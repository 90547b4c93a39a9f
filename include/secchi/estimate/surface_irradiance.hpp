#pragma once
// Irradiance on opaque surfaces (objects in the water, the bottom) from the surface photon map
// (map/surface_record.hpp): the density estimate of the arrivals near a point x on a surface of
// normal n (Jensen 2001, "Realistic Image Synthesis Using Photon Mapping", eq. 7.6, with the
// BRDF taken out: the irradiance alone),
//     E(x) = sum_i Phi_i / (pi r^2),  Phi_i = w_i Phi,
// over the arrivals i within distance r of x whose normal faces the same way as n
// (n_i . n >= min_normal_cosine: the photons on the other faces of a box's edge are not this
// face's), Phi the flux a map photon carries (RecordFlux::per_record). The disc of radius r is
// taken as lying in the surface: near a face's edge, or where the surface curves within r, E is
// underestimated (the disc's part off the surface holds no photons), as in any photon map.
// A Lambertian surface of albedo A then sends L = A E / pi.
//
// Standard error: each map batch b (a 1/B share of the map photons) gives its own estimate,
// B times its arrivals' sum, and E is their mean (core/stats.hpp batch_estimate).
//
// The arrivals are sorted into an n x n grid of columns over the section [0, W)^2, n = floor(W / r)
// (cells at least r wide), so a query reads the 3 x 3 columns about x, taken modulo n: the
// periodic copies of the section are searched alike, and a disc across its seam is whole.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/core/units.hpp"
#include "secchi/map/surface_record.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

namespace secchi::SECCHI_ISA {

class SurfaceIrradiance {
public:
    /// The arrivals of a first pass (TransportResult::surface_photons), the flux per unit
    /// weight (its map_flux.per_record), its batches, the section width W (m), the disc's radius
    /// r (m, at most W / 4) and the least cosine between a photon's normal and the query's.
    SurfaceIrradiance(std::vector<SurfacePhoton> photons, double flux_per_weight, unsigned batches, double width,
                      Radius gather, double min_normal_cosine = 0.5)
        : flux_(flux_per_weight), batches_(batches), width_(width), radius_(gather.value()), min_cos_(min_normal_cosine) {
        const double radius = radius_;
        require(std::isfinite(flux_per_weight) && flux_per_weight >= 0.0, "flux per record", flux_per_weight,
                "must be finite and >= 0");
        require(batches >= 2, "batches", batches, "must be >= 2 (standard errors)");
        require(std::isfinite(width) && width > 0.0, "section width (m)", width, "must be > 0");
        require(std::isfinite(radius) && radius > 0.0 && radius <= 0.25 * width, "surface gather radius (m)", radius,
                "must be > 0 and at most a quarter of the section width (" + std::to_string(0.25 * width) + " m)");
        require(min_normal_cosine >= -1.0 && min_normal_cosine <= 1.0, "least normal cosine", min_normal_cosine,
                "must be in [-1, 1]");
        cells_ = std::max(1u, static_cast<unsigned>(std::floor(width / radius)));
        // Counting sort of the arrivals into their columns.
        start_.assign(static_cast<std::size_t>(cells_) * cells_ + 1, 0);
        for (const SurfacePhoton& p : photons) {
            require(p.batch < batches, "surface photon batch", static_cast<unsigned>(p.batch),
                    "must be below the batches (" + std::to_string(batches) + ")");
            ++start_[column(p.point) + 1];
        }
        for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
        photons_.resize(photons.size());
        std::vector<std::size_t> next(start_.begin(), start_.end() - 1);
        for (const SurfacePhoton& p : photons) photons_[next[column(p.point)]++] = p;
    }

    [[nodiscard]] Radius radius() const { return Radius(radius_); }
    [[nodiscard]] std::size_t size() const { return photons_.size(); }

    /// E at the point x on a surface of unit normal n (facing the water), with its SE, in the
    /// first pass's units (its source's plane irradiance).
    [[nodiscard]] Estimate irradiance(const vec3& x, const vec3& n) const {
        std::vector<double> per_batch(batches_, 0.0);
        const double r2 = radius_ * radius_;
        const long ci = cell_of(x.x), cj = cell_of(x.y), n_cells = cells_;
        // The distinct columns within one of (ci, cj), modulo n (fewer than 9 when n < 3).
        std::array<std::size_t, 9> columns{};
        std::size_t k = 0;
        for (long dj = -1; dj <= 1; ++dj)
            for (long di = -1; di <= 1; ++di) {
                const long i = ((ci + di) % n_cells + n_cells) % n_cells, j = ((cj + dj) % n_cells + n_cells) % n_cells;
                columns[k++] = static_cast<std::size_t>(j * n_cells + i);
            }
        std::sort(columns.begin(), columns.end());
        const auto last = std::unique(columns.begin(), columns.end());
        for (auto c_it = columns.begin(); c_it != last; ++c_it) {
            for (std::size_t m = start_[*c_it]; m < start_[*c_it + 1]; ++m) {
                const SurfacePhoton& p = photons_[m];
                // The nearest periodic image of the arrival (r <= W / 4: one image within r at most).
                const vec3 d{nearest_image(p.point.x - x.x), nearest_image(p.point.y - x.y), p.point.z - x.z};
                if (glm::dot(d, d) < r2 && glm::dot(p.normal, n) >= min_cos_) per_batch[p.batch] += p.weight;
            }
        }
        const double scale = static_cast<double>(batches_) * flux_ / (std::numbers::pi * r2);
        for (double& v : per_batch) v *= scale;
        return batch_estimate(per_batch);
    }

private:
    [[nodiscard]] long cell_of(double v) const {
        return std::min<long>(cells_ - 1, static_cast<long>(periodic_wrap(v, width_) / width_ * cells_));
    }
    [[nodiscard]] std::size_t column(const vec3& p) const {
        return static_cast<std::size_t>(cell_of(p.y)) * cells_ + static_cast<std::size_t>(cell_of(p.x));
    }
    [[nodiscard]] double nearest_image(double d) const { return d - width_ * std::round(d / width_); }

    double flux_;
    unsigned batches_;
    double width_, radius_, min_cos_;
    unsigned cells_ = 1;
    std::vector<std::size_t> start_;  ///< column c holds photons_[start_[c], start_[c + 1])
    std::vector<SurfacePhoton> photons_;
};

}  // namespace secchi
